// Each phase is one move; poll() starts the next once the step generator is idle. A seek that
// runs its whole length without the switch, a switch still tripped once the table has left it, or
// a latch that finds it released, fails homing (grbl's homing contract). The switches are normally
// closed, so an unwired or cut one reads tripped everywhere: the seek "finds" it at once and the
// check after backing off catches it. Limits are read only on steps towards min, so each check is
// a one-step move towards the switch: the step interrupt reads it (debounced) and refuses the step
// if it is tripped.
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
  // The trip that ended a check move is homing's finding, not a hard-limit alarm of its own.
  if (motion_.trip() != Trip::kEstop) motion_.clear_trip();
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
      if (trip != own_trip()) {
        return fail(axis_ == 0 ? "x switch not found over the travel (jammed or shorted)"
                               : "y switch not found over the travel (jammed or shorted)");
      }
      phase_ = Phase::kBackoff;
      move_axis(c.home_backoff_steps, c.home_seek_rate_steps_s);
      return;
    case Phase::kBackoff:
      phase_ = Phase::kBackoffCheck;
      move_axis(-1, c.home_latch_rate_steps_s);
      return;
    case Phase::kBackoffCheck:
      if (trip == own_trip()) {
        return fail(axis_ == 0 ? "x switch still tripped 2 mm off it (unwired or cut)"
                               : "y switch still tripped 2 mm off it (unwired or cut)");
      }
      phase_ = Phase::kLatch;
      move_axis(-(c.home_backoff_steps * 2), c.home_latch_rate_steps_s);
      return;
    case Phase::kLatch: {
      if (trip != own_trip()) return fail(axis_ == 0 ? "x switch did not trip again on the slow approach" : "y switch did not trip again on the slow approach");
      // The slow approach's trip point is the axis's machine position.
      if (axis_ == 0) motion_.set_position(c.home_switch_steps, motion_.y_steps());
      else motion_.set_position(motion_.x_steps(), c.home_switch_steps);
      phase_ = Phase::kPullOff;
      // One step further than the pull-off: the check steps back onto the pull-off position.
      move_axis(c.home_pull_off_steps - c.home_switch_steps + 1, c.home_seek_rate_steps_s);
      return;
    }
    case Phase::kPullOff:
      phase_ = Phase::kPullOffCheck;
      move_axis(-1, c.home_latch_rate_steps_s);
      return;
    case Phase::kPullOffCheck:
      if (trip == own_trip()) {
        return fail(axis_ == 0 ? "x switch did not clear on pull-off" : "y switch did not clear on pull-off");
      }
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
