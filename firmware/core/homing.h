// Homing: per axis (x, then y) seek the min switch fast, back off, approach it slowly, take the
// switch point as the axis's machine position, pull off; after backing off and after pulling off
// the switch must read released. A state machine polled by the device.
#pragma once
#include <cstdint>

#include "digitizer.pb.h"
#include "firmware/core/step_generator.h"

namespace dg {

class Homing {
 public:
  explicit Homing(StepGenerator& motion) : motion_(motion) {}

  void start();
  // Advances; call whenever the motion may have stopped.
  void poll();
  bool active() const { return phase_ != Phase::kIdle && phase_ != Phase::kDone && phase_ != Phase::kFailed; }
  bool done() const { return phase_ == Phase::kDone; }
  bool failed() const { return phase_ == Phase::kFailed; }
  // Why it failed, for the fault message.
  const char* failure() const { return failure_; }
  void cancel();

 private:
  enum class Phase : uint8_t { kIdle, kSeek, kBackoff, kBackoffCheck, kLatch, kPullOff, kPullOffCheck, kDone, kFailed };
  void begin_axis();
  Status move_axis(int32_t steps, uint32_t rate);
  void fail(const char* why);
  Trip own_trip() const { return axis_ == 0 ? Trip::kLimitX : Trip::kLimitY; }

  StepGenerator& motion_;
  Phase phase_ = Phase::kIdle;
  int axis_ = 0;
  const char* failure_ = "";
};

}  // namespace dg
