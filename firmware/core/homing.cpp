// Each phase is one move; poll() starts the next once the step generator is idle. A seek that
// runs its whole length without the switch, or a latch that finds it released, fails homing.
#include "firmware/core/homing.h"

namespace dg {

void Homing::start() {
  axis_ = 0;
  begin_axis();
}

void Homing::cancel() {
  if (active()) motion_.stop();
  phase_ = Phase::kIdle;
}

void Homing::fail(const char* why) {
  motion_.stop();
  failure_ = why;
  phase_ = Phase::kFailed;
}

Status Homing::move_axis(int32_t steps, uint32_t rate) {
  motion_.clear_trip();
  return axis_ == 0 ? motion_.move_by_unchecked(steps, 0, rate) : motion_.move_by_unchecked(0, steps, rate);
}

void Homing::begin_axis() {
  const MotionConfig& c = motion_.config();
  // Far enough to cross the whole table and a margin. Starting on the switch, the seek trips at
  // once, and the back-off and slow approach find its edge as usual.
  const int32_t travel = (axis_ == 0 ? c.x_max_steps : c.y_max_steps) + 2 * c.home_backoff_steps;
  phase_ = Phase::kSeek;
  move_axis(-travel, c.home_seek_rate_steps_s);
}

void Homing::poll() {
  if (!active() || motion_.busy()) return;
  const MotionConfig& c = motion_.config();
  const Trip trip = motion_.trip();
  if (trip == Trip::kEstop) return fail("e-stop during homing");
  switch (phase_) {
    case Phase::kSeek:
      if (trip != own_trip()) return fail(axis_ == 0 ? "homing: the x min switch was not found" : "homing: the y min switch was not found");
      phase_ = Phase::kBackoff;
      move_axis(c.home_backoff_steps, c.home_seek_rate_steps_s);
      return;
    case Phase::kBackoff:
      if (trip != Trip::kNone) return fail("homing: a switch stayed closed while backing off");
      phase_ = Phase::kLatch;
      move_axis(-(c.home_backoff_steps * 2), c.home_latch_rate_steps_s);
      return;
    case Phase::kLatch: {
      if (trip != own_trip()) return fail(axis_ == 0 ? "homing: the x switch did not close again" : "homing: the y switch did not close again");
      // The slow approach's trip point is the axis's machine position.
      if (axis_ == 0) motion_.set_position(c.home_switch_steps, motion_.y_steps());
      else motion_.set_position(motion_.x_steps(), c.home_switch_steps);
      phase_ = Phase::kPullOff;
      move_axis(c.home_pull_off_steps - c.home_switch_steps, c.home_seek_rate_steps_s);
      return;
    }
    case Phase::kPullOff:
      if (trip != Trip::kNone) return fail("homing: stopped while pulling off");
      if (axis_ == 0) {
        axis_ = 1;
        motion_.clear_trip();
        begin_axis();
        return;
      }
      motion_.clear_trip();
      phase_ = Phase::kDone;
      return;
    default:
      return;
  }
}

}  // namespace dg
