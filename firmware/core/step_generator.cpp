// Step generation: a symmetric trapezoid (or triangle) in time, each step placed where constant
// acceleration from rest (or to rest) would put it, and no faster than the feed rate.
#include "firmware/core/step_generator.h"

namespace dg {

uint32_t isqrt64(uint64_t value) {
  uint64_t result = 0;
  uint64_t bit = uint64_t{1} << 62;
  while (bit > value) bit >>= 2;
  while (bit != 0) {
    if (value >= result + bit) {
      value -= result + bit;
      result = (result >> 1) + bit;
    } else {
      result >>= 1;
    }
    bit >>= 2;
  }
  return static_cast<uint32_t>(result);
}

StepGenerator::StepGenerator(hal::Board& board, const MotionConfig& config)
    : board_(board), config_(config), ramp_ns_(isqrt64(2000000000000000000ull / (config.accel_steps_s2 > 0 ? config.accel_steps_s2 : 1))) {}

void StepGenerator::set_position(int32_t x_steps, int32_t y_steps) {
  x_ = x_steps;
  y_ = y_steps;
}

Status StepGenerator::move_to(int32_t x_steps, int32_t y_steps, uint32_t rate_steps_s) {
  if (busy_) return Status::kBusy;
  if (x_steps < 0 || y_steps < 0 || x_steps > config_.x_max_steps ||
      y_steps > config_.y_max_steps) {
    return Status::kInvalidArgument;
  }
  return start(static_cast<int64_t>(x_steps) - x_, static_cast<int64_t>(y_steps) - y_, rate_steps_s);
}

Status StepGenerator::probe_to(int32_t x_steps, int32_t y_steps, uint32_t rate_steps_s, uint32_t overtravel_steps) {
  if (busy_) return Status::kBusy;
  // Braking from rate v takes v^2 / 2a steps: it must fit in the overtravel.
  const uint32_t rate = rate_steps_s == 0 || rate_steps_s > config_.max_rate_steps_s ? config_.max_rate_steps_s : rate_steps_s;
  if (static_cast<uint64_t>(rate) * rate > 2ull * config_.accel_steps_s2 * overtravel_steps) return Status::kInvalidArgument;
  touched_ = false;
  touch_edge_ = false;
  const Status s = move_to(x_steps, y_steps, rate);
  probing_ = s == Status::kOk && busy_;
  return s;
}

Status StepGenerator::move_by_unchecked(int32_t dx_steps, int32_t dy_steps, uint32_t rate_steps_s) {
  if (busy_) return Status::kBusy;
  return start(dx_steps, dy_steps, rate_steps_s);
}

Status StepGenerator::start(int64_t dx, int64_t dy, uint32_t rate_steps_s) {
  probing_ = false;
  if (dx == 0 && dy == 0) return Status::kOk;
  trip_ = Trip::kNone;
  confirming_ = false;
  step_x_ = dx > 0 ? 1 : (dx < 0 ? -1 : 0);
  step_y_ = dy > 0 ? 1 : (dy < 0 ? -1 : 0);
  count_x_ = static_cast<uint32_t>(dx < 0 ? -dx : dx);
  count_y_ = static_cast<uint32_t>(dy < 0 ? -dy : dy);
  total_ = count_x_ > count_y_ ? count_x_ : count_y_;
  stop_at_ = total_;
  done_ = 0;
  error_ = total_ / 2;
  rate_ = (rate_steps_s == 0 || rate_steps_s > config_.max_rate_steps_s)
              ? config_.max_rate_steps_s
              : rate_steps_s;
  // An axis that reverses first takes up the play, at the ramp's starting speed.
  takeup_x_ = step_x_ != 0 && step_x_ != last_dir_x_ ? config_.backlash_x_steps : 0;
  takeup_y_ = step_y_ != 0 && step_y_ != last_dir_y_ ? config_.backlash_y_steps : 0;
  if (step_x_ != 0) last_dir_x_ = static_cast<int8_t>(step_x_);
  if (step_y_ != 0) last_dir_y_ = static_cast<int8_t>(step_y_);
  // Direction first; the first step waits at least the driver's set-up time.
  if (step_x_ != 0) board_.write_pin(hal::Pin::kDirX, step_x_ > 0);
  if (step_y_ != 0) board_.write_pin(hal::Pin::kDirY, step_y_ > 0);
  busy_ = true;
  wait_left_ns_ = 0;
  const uint32_t first = period_ns(1);
  board_.start_step_timer(until_next_step(first > config_.dir_setup_ns ? first : config_.dir_setup_ns),
                          &StepGenerator::on_tick, this);
  return Status::kOk;
}

uint32_t StepGenerator::until_next_step(uint32_t period) {
  if (period <= kSafetyReadNs) return period;
  wait_left_ns_ = period - kSafetyReadNs;
  return kSafetyReadNs;
}

void StepGenerator::stop() {
  board_.stop_step_timer();
  busy_ = false;
}

uint64_t StepGenerator::ramp_time_ns(uint32_t k) const {
  // sqrt(k) in 44.20 fixed point, rounded up, times ramp_ns_ (5e6 ns at 80,000 steps/s^2): never
  // earlier than the exact time, and no overflow while k < 2^24 (ramps are far shorter).
  if (k == 0) return 0;
  return ((static_cast<uint64_t>(isqrt64(static_cast<uint64_t>(k) << 40)) + 1) * ramp_ns_) >> 20;
}

uint32_t StepGenerator::period_ns(uint32_t step_index) const {
  // Under constant acceleration from rest, step k happens at ramp_ns_ * sqrt(k): step k's period
  // is the difference of two such times, on the way up (k counted from the start) and down (from
  // the end), and never shorter than the feed rate's. Which one binds is decided on squared
  // speeds (2 a k against rate^2), so at cruise speed a tick takes no square root.
  const uint64_t two_a = 2ull * config_.accel_steps_s2;
  const uint64_t rate_sq = static_cast<uint64_t>(rate_) * rate_;
  uint64_t period = 1000000000u / (rate_ > 0 ? rate_ : 1);
  const uint32_t from_end = stop_at_ >= step_index ? stop_at_ - step_index + 1 : 1;
  const uint32_t nearest = step_index < from_end ? step_index : from_end;
  if (two_a * nearest < rate_sq && nearest < (1u << 24)) {
    const uint64_t ramp = ramp_time_ns(nearest) - ramp_time_ns(nearest - 1);
    if (ramp > period) period = ramp;
  }
  return period > 0xFFFFFFFFull ? 0xFFFFFFFFu : static_cast<uint32_t>(period);
}

uint32_t StepGenerator::halt(Trip trip) {
  // The e-stop cuts the drivers here, in the interrupt, not when the main loop next looks.
  if (trip == Trip::kEstop) board_.enable_drivers(false);
  trip_ = trip;
  busy_ = false;
  wait_left_ns_ = 0;
  return 0;
}

uint32_t StepGenerator::on_tick(void* self) { return static_cast<StepGenerator*>(self)->tick(); }

void StepGenerator::attach_estop() { board_.on_rising_edge(hal::Pin::kEstop, on_estop_edge, this); }

void StepGenerator::attach_probe() { board_.on_rising_edge(hal::Pin::kTouchProbe, on_probe_edge, this); }

void StepGenerator::on_probe_edge(void* self) {
  StepGenerator& g = *static_cast<StepGenerator*>(self);
  // The step interrupt outranks this one, so the counts are never half-way through a step here.
  if (!g.probing_ || g.touched_ || g.touch_edge_) return;
  g.touch_x_ = g.x_;
  g.touch_y_ = g.y_;
  g.touch_edge_ = true;
}

void StepGenerator::on_estop_edge(void* self) {
  StepGenerator& g = *static_cast<StepGenerator*>(self);
  // Debounced as every safety read is: asserted now and again kConfirmNs later. A spike on the
  // cable costs this interrupt kConfirmNs and nothing else.
  if (!g.board_.read_pin(hal::Pin::kEstop)) return;
  g.board_.spin_ns(kConfirmNs);
  if (!g.board_.read_pin(hal::Pin::kEstop)) return;
  g.board_.enable_drivers(false);
  g.estop_cut_ = true;
}

uint32_t StepGenerator::tick() {
  // The e-stop's edge already cut the drivers: no step goes to them.
  if (estop_cut_) return halt(Trip::kEstop);
  if (wait_left_ns_ > 0) {
    // A wake between two steps far apart (a ramp's first steps are milliseconds apart): only the
    // e-stop is read, confirmed like before a step, so that it stops the table within
    // kSafetyReadNs + kConfirmNs at any speed instead of at the next step.
    if (board_.read_pin(hal::Pin::kEstop)) {
      if (!confirming_) {
        confirming_ = true;
        return kConfirmNs;
      }
      confirming_ = false;
      return halt(Trip::kEstop);
    }
    confirming_ = false;
    const uint32_t next = wait_left_ns_ > kSafetyReadNs ? kSafetyReadNs : wait_left_ns_;
    wait_left_ns_ -= next;
    return next;
  }
  bool step_x = false, step_y = false;
  const int64_t error_before = error_;
  const bool takeup = takeup_x_ > 0 || takeup_y_ > 0;
  if (takeup) {
    // Backlash: motor steps that move no table, so they are not counted.
    step_x = takeup_x_ > 0;
    step_y = takeup_y_ > 0;
  } else if (count_x_ >= count_y_) {
    // Bresenham along the dominant axis keeps the path straight and the counts exact.
    step_x = true;
    error_ -= count_y_;
    if (error_ < 0) {
      step_y = true;
      error_ += total_;
    }
  } else {
    step_y = true;
    error_ -= count_x_;
    if (error_ < 0) {
      step_x = true;
      error_ += total_;
    }
  }
  // Safety inputs before the step: the axis stops within one step period of a switch closing.
  Trip trip = Trip::kNone;
  if (board_.read_pin(hal::Pin::kEstop)) trip = Trip::kEstop;
  else if (step_x && step_x_ < 0 && board_.read_pin(hal::Pin::kLimitXMin)) trip = Trip::kLimitX;
  else if (step_y && step_y_ < 0 && board_.read_pin(hal::Pin::kLimitYMin)) trip = Trip::kLimitY;
  if (trip != Trip::kNone && !confirming_) {
    // Debounce with bounded latency: an input seen asserted is read again kConfirmNs later before
    // it stops the move, and this step waits for that read. A spike shorter than that (noise on a
    // long switch cable) costs one step kConfirmNs late instead of an alarm.
    confirming_ = true;
    error_ = error_before;
    return kConfirmNs;
  }
  confirming_ = false;
  if (trip != Trip::kNone) return halt(trip);
  // Touch probe: latch where the stylus was deflected, then brake to rest in the fewest steps the
  // acceleration allows (probe_to made sure they fit in the overtravel).
  // An edge latched the counts at the moment the contacts opened (the same counts this read
  // would give, since the table moves only at a step); a stylus that is no longer deflected here
  // bounced, and is no touch.
  const bool awaiting_touch = probing_ && !touched_;
  const bool deflected = awaiting_touch && board_.read_pin(hal::Pin::kTouchProbe);
  if (awaiting_touch && !deflected) touch_edge_ = false;
  if (deflected) {
    if (!touch_edge_) {
      touch_x_ = x_;
      touch_y_ = y_;
    }
    touched_ = true;
    const uint64_t speed = 1000000000ull / period_ns(done_ > 0 ? done_ : 1);
    const uint32_t braking = static_cast<uint32_t>(speed * speed / (2ull * config_.accel_steps_s2));
    stop_at_ = done_ + braking;
    if (stop_at_ <= done_ || braking == 0) {
      busy_ = false;
      return 0;
    }
  }
  if (step_x) board_.write_pin(hal::Pin::kStepX, true);
  if (step_y) board_.write_pin(hal::Pin::kStepY, true);
  if (takeup) {
    if (step_x) {
      --takeup_x_;
      board_.write_pin(hal::Pin::kStepX, false);
    }
    if (step_y) {
      --takeup_y_;
      board_.write_pin(hal::Pin::kStepY, false);
    }
    return until_next_step(period_ns(1));
  }
  if (step_x) {
    x_ = x_ + step_x_;
    board_.write_pin(hal::Pin::kStepX, false);
  }
  if (step_y) {
    y_ = y_ + step_y_;
    board_.write_pin(hal::Pin::kStepY, false);
  }
  ++done_;
  if (done_ >= stop_at_) {
    busy_ = false;
    return 0;
  }
  return until_next_step(period_ns(done_ + 1));
}

}  // namespace dg
