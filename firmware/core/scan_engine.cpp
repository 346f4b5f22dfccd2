// The scan state machine. Each point: move -> settle -> read (N samples, retries) -> emit.
#include "firmware/core/scan_engine.h"

#include "common/proto/scan_grid.h"

namespace dg {

ScanEngine::ScanEngine(hal::Board& board, StepGenerator& motion, Probe& gauge,
                       ScanLimits limits)
    : board_(board), motion_(motion), gauge_(gauge), limits_(limits) {}

int32_t ScanEngine::to_steps(int64_t nm) const {
  const int64_t per = motion_.config().nm_per_step;
  // Round half away from zero so symmetric requests stay symmetric.
  return static_cast<int32_t>(nm >= 0 ? (nm + per / 2) / per : -((-nm + per / 2) / per));
}

digitizer_FaultCode ScanEngine::start(const digitizer_ScanRequest& request, uint32_t first_seq,
                                      uint32_t default_feed_um_s, const char** reason) {
  if (active()) {
    *reason = "a scan is already running";
    return digitizer_FaultCode_FAULT_BUSY;
  }
  if (!request.has_x || !request.has_y || request.x.max_nm < request.x.min_nm ||
      request.y.max_nm < request.y.min_nm) {
    *reason = "scan extent missing or max < min";
    return digitizer_FaultCode_FAULT_BAD_REQUEST;
  }
  const uint32_t resolution = motion_.config().nm_per_step;
  if (request.step_x_nm < resolution || request.step_y_nm < resolution) {
    *reason = "step smaller than one motor step";
    return digitizer_FaultCode_FAULT_BAD_REQUEST;
  }
  // Which gauge is wired is the device's to check (Device refuses a request for another).
  if (request.samples_per_point > limits_.max_samples_per_point ||
      request.samples_per_point > sizeof(samples_nm_) / sizeof(samples_nm_[0])) {
    *reason = "too many samples per point";
    return digitizer_FaultCode_FAULT_BAD_REQUEST;
  }
  ScanGrid grid;
  scan_grid(request, &grid);  // extent and steps were checked above
  if (grid.readings() > limits_.max_points) {
    *reason = "more points than the device accepts in one scan";
    return digitizer_FaultCode_FAULT_BAD_REQUEST;
  }
  const MotionConfig& m = motion_.config();
  const int32_t x0 = to_steps(request.x.min_nm), x1 = to_steps(request.x.max_nm);
  const int32_t y0 = to_steps(request.y.min_nm), y1 = to_steps(request.y.max_nm);
  if (x0 < 0 || y0 < 0 || x1 > m.x_max_steps || y1 > m.y_max_steps) {
    *reason = "scan extent outside the table";
    return digitizer_FaultCode_FAULT_SOFT_LIMIT;
  }
  const bool fly = flies(request);
  if (fly && (*reason = fly_refusal(request)) != nullptr) return digitizer_FaultCode_FAULT_BAD_REQUEST;
  if (!fly && scan_mode_number(request) != digitizer_ScanMode_SCAN_MODE_STOP) {
    *reason = "unknown scan mode";
    return digitizer_FaultCode_FAULT_BAD_REQUEST;
  }
  request_ = request;
  fly_ = fly;
  fly_lo_steps_ = x0, fly_hi_steps_ = x1;
  fly_reading_ = fly_held_ = fly_waiting_ = false;
  fly_failures_ = 0;
  cycle_us_ = 0;  // every fly scan times the gauge afresh: its step and feed cap set the feed
  plunger_um_s_ = request.plunger_follow_um_s != 0 ? request.plunger_follow_um_s : kDefaultPlungerFollowUmS;
  {
    // The run-up: the distance the table needs to reach the fastest feed (v^2 / 2a), and a step.
    const uint64_t v = m.max_rate_steps_s, a = m.accel_steps_s2 > 0 ? m.accel_steps_s2 : 1;
    fly_runup_steps_ = static_cast<int32_t>(v * v / (2 * a) + 1);
  }
  count_x_ = static_cast<uint32_t>(grid.points_per_line);
  count_y_ = static_cast<uint32_t>(grid.lines);
  references_total_ = static_cast<uint32_t>(grid.references);
  const uint32_t feed = request.feed_um_s != 0 ? request.feed_um_s : default_feed_um_s;
  rate_steps_s_ = static_cast<uint32_t>(static_cast<uint64_t>(feed) * 1000 / resolution);
  if (rate_steps_s_ == 0) rate_steps_s_ = 1;
  ix_ = iy_ = 0;
  next_seq_ = first_seq_ = first_seq;
  points_done_ = lines_done_ = 0;
  paused_ = abort_requested_ = holding_ = reference_due_ = in_reference_ = false;
  end_ = digitizer_ScanEnd_SCAN_COMPLETED;
  fault_ = digitizer_FaultCode_FAULT_NONE;
  started_us_ = board_.now_us();
  begin_point();
  return digitizer_FaultCode_FAULT_NONE;
}

bool ScanEngine::take_reading(int64_t value_nm) {
  // Settling: after a move the gauge's spindle may still creep; wait for two readings that agree.
  if (request_.settle_tolerance_nm > 0 && samples_taken_ == 0 && settle_reads_ < limits_.max_settle_reads) {
    const bool agrees = settle_reads_ > 0 && (value_nm > previous_nm_ ? value_nm - previous_nm_ : previous_nm_ - value_nm) <=
                                                 static_cast<int64_t>(request_.settle_tolerance_nm);
    ++settle_reads_;
    previous_nm_ = value_nm;
    if (!agrees) {
      if (settle_reads_ == limits_.max_settle_reads) point_flags_ |= digitizer_PointFlag_POINT_SPREAD_HIGH;
      return false;
    }
  }
  samples_nm_[samples_taken_] = value_nm;
  z_sum_nm_ += value_nm;
  ++samples_taken_;
  uint32_t wanted = request_.samples_per_point > 1 ? request_.samples_per_point : 1;
  // A reference reading corrects every point near it in time, so its noise goes into all of them:
  // it averages at least kReferenceSamples readings.
  if (in_reference_ && wanted < kReferenceSamples) wanted = kReferenceSamples;
  if (samples_taken_ < wanted) return false;
  if (request_.spread_tolerance_nm > 0) {
    int64_t lo = samples_nm_[0], hi = samples_nm_[0];
    for (uint32_t i = 1; i < samples_taken_; ++i) {
      lo = samples_nm_[i] < lo ? samples_nm_[i] : lo;
      hi = samples_nm_[i] > hi ? samples_nm_[i] : hi;
    }
    if (hi - lo > static_cast<int64_t>(request_.spread_tolerance_nm)) {
      if (!spread_retried_) {
        // Once more from the start: a knock or a creeping spindle rarely repeats.
        spread_retried_ = true;
        point_flags_ |= digitizer_PointFlag_POINT_RETRIED;
        samples_taken_ = 0;
        z_sum_nm_ = 0;
        return false;
      }
      point_flags_ |= digitizer_PointFlag_POINT_SPREAD_HIGH;
    }
  }
  return true;
}

int64_t ScanEngine::point_value() const {
  const int64_t n = samples_taken_;
  if (request_.median && n > 1) {
    // Insertion sort of at most 16 values, then the middle (the mean of the two middle ones).
    int64_t sorted[16];
    for (int64_t i = 0; i < n; ++i) {
      int64_t j = i;
      while (j > 0 && sorted[j - 1] > samples_nm_[i]) {
        sorted[j] = sorted[j - 1];
        --j;
      }
      sorted[j] = samples_nm_[i];
    }
    const int64_t a = sorted[(n - 1) / 2], b = sorted[n / 2];
    const int64_t sum = a + b;
    return sum >= 0 ? (sum + 1) / 2 : -((-sum + 1) / 2);
  }
  // The mean, rounded to the nearest nanometre.
  return z_sum_nm_ >= 0 ? (z_sum_nm_ + n / 2) / n : -((-z_sum_nm_ + n / 2) / n);
}

uint32_t ScanEngine::line_first_seq(uint32_t line) const {
  if (fly_) {
    // A line more than kFlyLinesKept back: its points are acknowledged long since; the oldest kept.
    // The scan's first line starts at its first point, whatever came after.
    if (line == 0) return first_seq_;
    const uint32_t oldest = iy_ >= kFlyLinesKept ? iy_ - kFlyLinesKept + 1 : 0;
    return fly_first_seq_[(line < oldest ? oldest : line) % kFlyLinesKept];
  }
  const uint32_t every = request_.reference_every_lines;
  return first_seq_ + line * count_x_ + (every > 0 ? line / every : 0);
}

void ScanEngine::begin_point() {
  if (fly_) {
    begin_fly_line();
    return;
  }
  if (reference_due_) {
    begin_reference();
    return;
  }
  // Serpentine lines run backwards on odd rows to save the return move.
  const bool reverse = request_.pattern == digitizer_ScanPattern_PATTERN_SERPENTINE && (iy_ & 1u);
  const uint32_t column = reverse ? count_x_ - 1 - ix_ : ix_;
  const int64_t x_nm = static_cast<int64_t>(request_.x.min_nm) +
                       static_cast<int64_t>(column) * request_.step_x_nm;
  const int64_t y_nm = static_cast<int64_t>(request_.y.min_nm) +
                       static_cast<int64_t>(iy_) * request_.step_y_nm;
  begin_move(x_nm, y_nm);
}

void ScanEngine::begin_reference() {
  // The scan's first point, reached the way every point is (the approach included), so its
  // readings differ from the first one's only by what changed since: the gauge stand's drift.
  reference_due_ = false;
  in_reference_ = true;
  begin_move(request_.x.min_nm, request_.y.min_nm);
}

void ScanEngine::begin_move(int64_t x_nm, int64_t y_nm) {
  target_x_ = to_steps(x_nm);
  target_y_ = to_steps(y_nm);
  // Single-direction approach: an axis about to arrive moving towards min overshoots first.
  const int32_t over = to_steps(request_.approach_nm);
  int32_t via_x = target_x_, via_y = target_y_;
  if (over > 0 && target_x_ < motion_.x_steps()) via_x = target_x_ - over > 0 ? target_x_ - over : 0;
  if (over > 0 && target_y_ < motion_.y_steps()) via_y = target_y_ - over > 0 ? target_y_ - over : 0;
  const bool detour = via_x != target_x_ || via_y != target_y_;
  const Status moved = motion_.move_to(via_x, via_y, rate_steps_s_);
  if (moved != Status::kOk) {
    finish(digitizer_ScanEnd_SCAN_FAULTED, digitizer_FaultCode_FAULT_SOFT_LIMIT);
    return;
  }
  samples_taken_ = 0;
  retries_left_ = limits_.probe_retries;
  z_sum_nm_ = 0;
  settle_reads_ = 0;
  spread_retried_ = false;
  point_flags_ = 0;
  phase_ = detour ? Phase::kApproaching : Phase::kMoving;
}

void ScanEngine::finish(digitizer_ScanEnd why, digitizer_FaultCode fault) {
  motion_.stop();
  end_ = why;
  fault_ = fault;
  finished_us_ = board_.now_us();
  phase_ = Phase::kFinished;
}

void ScanEngine::count_emitted() {
  ++next_seq_;
  ++points_done_;
  if (in_reference_) {
    in_reference_ = false;
    end_line();
    return;
  }
  if (++ix_ == count_x_) {
    if (reference_after(iy_)) {
      reference_due_ = true;  // the line ends with its reference reading
    } else {
      end_line();
    }
  }
}

void ScanEngine::end_line() {
  ix_ = 0;
  ++lines_done_;
  ++iy_;
}

void ScanEngine::abort() {
  if (active()) abort_requested_ = true;
}

uint64_t ScanEngine::deadline_us() const {
  if (phase_ == Phase::kSettling) return settle_until_us_;
  if (phase_ == Phase::kReading) return gauge_.deadline_us();
  if ((phase_ == Phase::kTiming || phase_ == Phase::kFlying) && fly_reading_) return gauge_.deadline_us();
  return UINT64_MAX;
}

void ScanEngine::poll(PointSink& sink) {
  // Each pass may finish one phase and start the next, so loop until nothing changes.
  for (int guard = 0; guard < 8; ++guard) {
    const Phase before = phase_;
    switch (phase_) {
      case Phase::kIdle:
        return;
      case Phase::kFinished:
        // A scan aborted while its last point waited for room in the ring: the point was measured,
        // so it goes in as soon as there is room (the ScanDone waits for it: holding_point()).
        // On the fly the line's held point follows it.
        while (holding_ && sink.accept(pending_)) {
          holding_ = false;
          if (fly_) {
            ++next_seq_, ++points_done_;
          } else {
            count_emitted();
          }
          if (fly_held_) {
            pend_held_point(digitizer_PointFlag_POINT_LINE_END);
            holding_ = true;
          }
        }
        return;
      case Phase::kRunUp:
      case Phase::kTiming:
      case Phase::kFlying:
        poll_fly(sink);
        break;
      case Phase::kApproaching:
        if (abort_requested_) {
          finish(digitizer_ScanEnd_SCAN_ABORTED, digitizer_FaultCode_FAULT_NONE);
          return;
        }
        if (motion_.busy()) return;
        if (motion_.move_to(target_x_, target_y_, rate_steps_s_) != Status::kOk) {
          finish(digitizer_ScanEnd_SCAN_FAULTED, digitizer_FaultCode_FAULT_SOFT_LIMIT);
          return;
        }
        phase_ = Phase::kMoving;
        break;
      case Phase::kMoving:
        if (abort_requested_) {
          finish(digitizer_ScanEnd_SCAN_ABORTED, digitizer_FaultCode_FAULT_NONE);
          return;
        }
        if (motion_.busy()) return;
        settle_until_us_ = board_.now_us() + static_cast<uint64_t>(request_.settle_ms) * 1000;
        phase_ = Phase::kSettling;
        break;
      case Phase::kSettling:
        if (board_.now_us() < settle_until_us_) return;
        gauge_.start();
        phase_ = Phase::kReading;
        break;
      case Phase::kReading: {
        const Probe::State state = gauge_.poll();
        if (state == Probe::State::kReading) return;
        if (state == Probe::State::kFailed) {
          if (retries_left_ == 0) {
            finish(digitizer_ScanEnd_SCAN_FAULTED, gauge_.error() == Status::kTimeout
                                                       ? digitizer_FaultCode_FAULT_PROBE_TIMEOUT
                                                       : digitizer_FaultCode_FAULT_PROBE_FRAME);
            return;
          }
          --retries_left_;
          point_flags_ |= digitizer_PointFlag_POINT_RETRIED;
          gauge_.start();
          return;
        }
        if (!take_reading(gauge_.value_nm())) {
          gauge_.start();
          return;
        }
        pending_.seq = next_seq_;
        pending_.line = iy_;
        pending_.x_nm = static_cast<int32_t>(static_cast<int64_t>(motion_.x_steps()) *
                                             motion_.config().nm_per_step);
        pending_.y_nm = static_cast<int32_t>(static_cast<int64_t>(motion_.y_steps()) *
                                             motion_.config().nm_per_step);
        pending_.z_nm = static_cast<int32_t>(point_value());
        pending_.t_us = board_.now_us();
        pending_.flags = point_flags_;
        if (in_reference_) {
          pending_.flags |= digitizer_PointFlag_POINT_REFERENCE | digitizer_PointFlag_POINT_LINE_END;
        } else {
          if (ix_ == 0) pending_.flags |= digitizer_PointFlag_POINT_LINE_START;
          if (ix_ + 1 == count_x_ && !reference_after(iy_)) pending_.flags |= digitizer_PointFlag_POINT_LINE_END;
        }
        last_z_nm_ = pending_.z_nm;
        phase_ = Phase::kEmitting;
        break;
      }
      case Phase::kEmitting:
        if (!sink.accept(pending_)) {
          // Ring full: wait, never drop. An abort does not wait for a host to make room (it may
          // be gone): the scan ends now and keeps the point until there is room.
          if (abort_requested_) {
            holding_ = true;
            finish(digitizer_ScanEnd_SCAN_ABORTED, digitizer_FaultCode_FAULT_NONE);
          }
          return;
        }
        count_emitted();
        if (iy_ == count_y_) {
          finish(digitizer_ScanEnd_SCAN_COMPLETED, digitizer_FaultCode_FAULT_NONE);
          return;
        }
        if (abort_requested_) {
          finish(digitizer_ScanEnd_SCAN_ABORTED, digitizer_FaultCode_FAULT_NONE);
          return;
        }
        if (paused_) {
          phase_ = Phase::kPaused;  // pauses between points, never inside a reading
          return;
        }
        begin_point();
        break;
      case Phase::kPaused:
        if (abort_requested_) {
          finish(digitizer_ScanEnd_SCAN_ABORTED, digitizer_FaultCode_FAULT_NONE);
          return;
        }
        if (paused_) return;
        begin_point();
        break;
    }
    if (phase_ == before) return;
  }
}

}  // namespace dg
