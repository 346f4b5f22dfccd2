// Step generation. The speed at dominant-axis step k of n is
// min(v_max, sqrt(2 a k), sqrt(2 a (n - k + 1))): a symmetric trapezoid (or triangle).
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
    : board_(board), config_(config) {}

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

Status StepGenerator::move_by_unchecked(int32_t dx_steps, int32_t dy_steps, uint32_t rate_steps_s) {
  if (busy_) return Status::kBusy;
  return start(dx_steps, dy_steps, rate_steps_s);
}

Status StepGenerator::start(int64_t dx, int64_t dy, uint32_t rate_steps_s) {
  if (dx == 0 && dy == 0) return Status::kOk;
  trip_ = Trip::kNone;
  step_x_ = dx > 0 ? 1 : (dx < 0 ? -1 : 0);
  step_y_ = dy > 0 ? 1 : (dy < 0 ? -1 : 0);
  count_x_ = static_cast<uint32_t>(dx < 0 ? -dx : dx);
  count_y_ = static_cast<uint32_t>(dy < 0 ? -dy : dy);
  total_ = count_x_ > count_y_ ? count_x_ : count_y_;
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
  const uint32_t first = period_ns(1);
  board_.start_step_timer(first > config_.dir_setup_ns ? first : config_.dir_setup_ns,
                          &StepGenerator::on_tick, this);
  return Status::kOk;
}

void StepGenerator::stop() {
  board_.stop_step_timer();
  busy_ = false;
}

uint32_t StepGenerator::period_ns(uint32_t step_index) const {
  // min(v_max, sqrt(2 a k), sqrt(2 a (n - k + 1))), with each square root taken only when it is
  // the smaller (compared as squares): at cruise speed a tick needs none.
  const uint64_t two_a = 2ull * config_.accel_steps_s2;
  uint32_t v = rate_;
  const uint64_t up_sq = two_a * step_index;
  if (up_sq < static_cast<uint64_t>(v) * v) v = isqrt64(up_sq);
  const uint64_t down_sq = two_a * (total_ - step_index + 1);
  if (down_sq < static_cast<uint64_t>(v) * v) v = isqrt64(down_sq);
  if (v == 0) v = 1;
  return 1000000000u / v;  // a 32-bit division: one instruction on a Cortex-M3/M4
}

uint32_t StepGenerator::on_tick(void* self) { return static_cast<StepGenerator*>(self)->tick(); }

uint32_t StepGenerator::tick() {
  bool step_x = false, step_y = false;
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
  if (trip != Trip::kNone) {
    trip_ = trip;
    busy_ = false;
    return 0;
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
    return period_ns(1);
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
  if (done_ >= total_) {
    busy_ = false;
    return 0;
  }
  return period_ns(done_ + 1);
}

}  // namespace dg
