// Scanning on the fly: each line at constant feed with readings back to back, every point where the
// table was when its reading was requested (the host corrects the gauge's latch delay after it).
#include "firmware/core/scan_engine.h"

namespace dg {

const char* ScanEngine::fly_refusal(const digitizer_ScanRequest& request) const {
  // The two directions of a serpentine are what measures the gauge's latch delay on the host.
  if (request.pattern != digitizer_ScanPattern_PATTERN_SERPENTINE) return "on the fly the lines run serpentine";
  if (request.samples_per_point > 1 || request.median || request.settle_tolerance_nm > 0 ||
      request.spread_tolerance_nm > 0) {
    return "on the fly every point is one reading (no samples, settling or spread check)";
  }
  // A reference reading compares the first point read at rest; on the fly there is no such point.
  if (request.reference_every_lines > 0) return "reference readings are for stop-and-go scans";
  return nullptr;
}

void ScanEngine::begin_fly_line() {
  fly_dir_ = (iy_ & 1u) ? -1 : 1;
  fly_first_ = true;
  fly_prev_ = false;  // a line's first reading has none before it to be judged against
  fly_gap_ = fly_again_ = false;
  fly_first_seq_[iy_ % kFlyLinesKept] = next_seq_;
  begin_fly_run(false);
}

void ScanEngine::begin_fly_run(bool again) {
  fly_again_ = again;
  fly_requested_ = false;
  // The run-up before the extent, as far as the table allows (short of it the first points are
  // taken while the table still speeds up; their positions stay exact, their spacing does not).
  const int32_t start = fly_dir_ > 0 ? fly_lo_steps_ - fly_runup_steps_ : fly_hi_steps_ + fly_runup_steps_;
  const int32_t max = motion_.config().x_max_steps;
  target_x_ = start < 0 ? 0 : start > max ? max : start;
  target_y_ = to_steps(static_cast<int64_t>(request_.y.min_nm) + static_cast<int64_t>(iy_) * request_.step_y_nm);
  if (motion_.move_to(target_x_, target_y_, rate_steps_s_) != Status::kOk) {
    finish(digitizer_ScanEnd_SCAN_FAULTED, digitizer_FaultCode_FAULT_SOFT_LIMIT);
    return;
  }
  phase_ = Phase::kRunUp;
}

bool ScanEngine::passed_readings_by(int32_t to_steps) {
  if (phase_ != Phase::kFlying || !fly_requested_ || fly_gap_) return false;
  // The stretch of the extent between the last request and `to_steps`: more than two steps of the
  // line is readings passed by (a wait for room in the ring, failed readings, or a flight that
  // ended while it waited).
  auto clamp = [this](int32_t x) { return x < fly_lo_steps_ ? fly_lo_steps_ : x > fly_hi_steps_ ? fly_hi_steps_ : x; };
  const int64_t passed_nm = static_cast<int64_t>(clamp(to_steps) - clamp(fly_req_x_)) * fly_dir_ * motion_.config().nm_per_step;
  if (passed_nm <= 2 * static_cast<int64_t>(request_.step_x_nm)) return false;
  // The rest of the line is flown again after the last point kept.
  fly_gap_ = true;
  fly_gap_from_ = fly_held_ ? static_cast<int32_t>(fly_point_.x_nm / static_cast<int32_t>(motion_.config().nm_per_step))
                            : (fly_dir_ > 0 ? fly_lo_steps_ - 1 : fly_hi_steps_ + 1);
  return true;
}

void ScanEngine::start_fly_reading() {
  const int32_t at = motion_.x_steps();
  if (passed_readings_by(at)) return;
  // The position is taken with the request: the reading belongs to where the table is now (and to
  // the gauge's latch delay after it, which the host measures).
  fly_req_us_ = board_.now_us();
  fly_req_x_ = at;
  fly_requested_ = true;
  fly_reading_ = gauge_.start() == Status::kOk;
}

bool ScanEngine::offer_fly_point(PointSink& sink) {
  fly_waiting_ = !sink.accept(pending_);
  if (!fly_waiting_) {
    ++next_seq_;
    ++points_done_;
    last_z_nm_ = pending_.z_nm;
  }
  return !fly_waiting_;
}

void ScanEngine::take_fly_reading(int64_t value_nm) {
  // Readings requested in the run-up or the run-out are outside the scan; flying a line again,
  // so are the ones short of its gap.
  if (fly_req_x_ < fly_lo_steps_ || fly_req_x_ > fly_hi_steps_) return;
  // The lift check compares a reading with the one before it in this flight, kept or not: after a
  // gap the held point is from the flight before, seconds earlier, against which a reading in the
  // air fell too slowly to be flagged (seen on the dome when a slow host made lines fly again).
  const bool judged = fly_prev_;
  const int32_t prev_z_nm = fly_prev_z_nm_;
  const uint64_t prev_us = fly_prev_us_;
  fly_prev_ = true;
  fly_prev_z_nm_ = static_cast<int32_t>(value_nm);
  fly_prev_us_ = fly_req_us_;
  if (fly_again_ && (fly_dir_ > 0 ? fly_req_x_ <= fly_gap_from_ : fly_req_x_ >= fly_gap_from_)) return;
  fly_again_ = false;  // past the gap: what follows is this flight's own
  PointSample point{};
  point.line = iy_;
  point.x_nm = static_cast<int32_t>(static_cast<int64_t>(fly_req_x_) * motion_.config().nm_per_step);
  point.y_nm = static_cast<int32_t>(static_cast<int64_t>(motion_.y_steps()) * motion_.config().nm_per_step);
  point.z_nm = static_cast<int32_t>(value_nm);
  point.t_us = fly_req_us_;
  point.flags = fly_first_ ? digitizer_PointFlag_POINT_LINE_START : 0;
  if (judged) {
    // Falling at 80 % of the plunger's speed or faster (nm/us is mm/s): it was probably off the part.
    const int64_t fell_nm = static_cast<int64_t>(prev_z_nm) - point.z_nm;
    const uint64_t dt_us = point.t_us - prev_us;
    if (fell_nm > 0 && static_cast<uint64_t>(fell_nm) * 1000u * 5u >= uint64_t{plunger_um_s_} * 4u * dt_us) {
      point.flags |= digitizer_PointFlag_POINT_LIFTED;
    }
  }
  if (fly_held_) {
    pend_held_point(0);
    fly_waiting_ = true;  // offered by poll_fly
  }
  fly_first_ = false;
  fly_point_ = point;
  fly_held_ = true;
}

void ScanEngine::end_fly_line(PointSink& sink) {
  // A flight that ended short of the extent's far end (it waited for room to its end) has a gap too.
  passed_readings_by(fly_dir_ > 0 ? fly_hi_steps_ : fly_lo_steps_);
  if (fly_gap_) {
    // Readings were passed by while the ring was full: the line again from its gap, once there is
    // room (a host that is gone pauses the scan meanwhile: Device's silence rule).
    if (sink.room() < kFlyRoomToFlyAgain) return;
    fly_gap_ = false;
    begin_fly_run(true);
    return;
  }
  if (fly_held_) {
    pend_held_point(digitizer_PointFlag_POINT_LINE_END);
    if (!offer_fly_point(sink)) return;  // the next poll offers it again, then ends the line
  }
  end_line();
  if (iy_ == count_y_) {
    finish(digitizer_ScanEnd_SCAN_COMPLETED, digitizer_FaultCode_FAULT_NONE);
  } else if (abort_requested_) {
    finish(digitizer_ScanEnd_SCAN_ABORTED, digitizer_FaultCode_FAULT_NONE);
  } else if (paused_) {
    phase_ = Phase::kPaused;  // pauses between lines, never inside one
  } else {
    begin_fly_line();
  }
}

void ScanEngine::poll_fly(PointSink& sink) {
  if (abort_requested_) {
    // Measured points are kept: the one waiting for room, then the held one (holding_point()).
    if (fly_waiting_) {
      fly_waiting_ = false;
      holding_ = true;
    } else if (fly_held_) {
      pend_held_point(digitizer_PointFlag_POINT_LINE_END);
      holding_ = true;
    }
    finish(digitizer_ScanEnd_SCAN_ABORTED, digitizer_FaultCode_FAULT_NONE);
    return;
  }
  if (fly_waiting_ && !offer_fly_point(sink)) return;
  if (phase_ == Phase::kRunUp) {
    if (motion_.busy()) return;
    if (cycle_us_ == 0) {
      start_fly_reading();
      phase_ = Phase::kTiming;
      return;
    }
    // The run-out past the extent's far end, as long as the run-up (the table allowing).
    const int32_t end = fly_dir_ > 0 ? fly_hi_steps_ + fly_runup_steps_ : fly_lo_steps_ - fly_runup_steps_;
    const int32_t max = motion_.config().x_max_steps;
    if (motion_.move_to(end < 0 ? 0 : end > max ? max : end, target_y_, fly_rate_steps_s_) != Status::kOk) {
      finish(digitizer_ScanEnd_SCAN_FAULTED, digitizer_FaultCode_FAULT_SOFT_LIMIT);
      return;
    }
    phase_ = Phase::kFlying;
    start_fly_reading();
    return;
  }
  if (fly_reading_) {
    const Probe::State state = gauge_.poll();
    if (state == Probe::State::kReading) return;
    fly_reading_ = false;
    if (state == Probe::State::kFailed) {
      // A failed reading makes no point; the next one starts at once. Several in a row: the gauge.
      if (++fly_failures_ > limits_.probe_retries) {
        finish(digitizer_ScanEnd_SCAN_FAULTED, gauge_.error() == Status::kTimeout ? digitizer_FaultCode_FAULT_PROBE_TIMEOUT
                                                                                   : digitizer_FaultCode_FAULT_PROBE_FRAME);
        return;
      }
      if (phase_ == Phase::kTiming) {
        start_fly_reading();  // the cycle is timed on a reading that arrived
        return;
      }
    } else {
      fly_failures_ = 0;
      if (phase_ == Phase::kTiming) {
        // The feed that puts one reading every step_x_nm, with 5 % to spare for the main loop's
        // turn between readings; never over the request's feed nor the motors' fastest.
        const uint64_t cycle_us = board_.now_us() - fly_req_us_;
        cycle_us_ = static_cast<uint32_t>((cycle_us > 0 ? cycle_us : 1) * 21 / 20);
        uint64_t rate = uint64_t{request_.step_x_nm} * 1000000u / cycle_us_ / motion_.config().nm_per_step;
        const uint64_t cap = request_.feed_um_s != 0 ? rate_steps_s_ : motion_.config().max_rate_steps_s;
        if (rate > cap) rate = cap;
        fly_rate_steps_s_ = rate > 0 ? static_cast<uint32_t>(rate) : 1;
        phase_ = Phase::kRunUp;  // at the run-up's start already: the line begins at the next poll
        return;
      }
      take_fly_reading(gauge_.value_nm());
      if (fly_waiting_ && !offer_fly_point(sink)) return;
    }
  }
  if (motion_.busy()) {
    if (!fly_gap_) start_fly_reading();
    return;
  }
  end_fly_line(sink);
}

}  // namespace dg
