// The repeatability command: the same point read N times, the table moved 1 mm away and back (from
// the same side) before each reading, so the spread covers positioning and the gauge together.
#pragma once
#include <cstdint>

#include "digitizer.pb.h"
#include "firmware/core/probe.h"
#include "firmware/core/step_generator.h"

namespace dg {

class RepeatabilityRun {
 public:
  RepeatabilityRun(StepGenerator& motion, Probe& probe) : motion_(motion), probe_(probe) {}

  // Starts at the current position; false when count is out of 2..64 or the table is busy.
  bool start(uint32_t count, uint32_t request_id);
  // Advances; true once when the run has ended (result() is then valid, or failed()).
  bool poll();
  bool active() const { return phase_ != Phase::kIdle; }
  bool failed() const { return failed_; }
  uint32_t request_id() const { return request_id_; }
  const digitizer_Repeatability& result() const { return result_; }
  void cancel();
  uint64_t deadline_us() const { return phase_ == Phase::kReading ? probe_.deadline_us() : UINT64_MAX; }

 private:
  enum class Phase : uint8_t { kIdle, kAway, kBack, kReading };
  void finish();
  // Starts the move 1 mm away; false (and the run cancelled) when it is refused.
  bool move_away();

  StepGenerator& motion_;
  Probe& probe_;
  Phase phase_ = Phase::kIdle;
  uint32_t count_ = 0, taken_ = 0, request_id_ = 0;
  int32_t home_x_ = 0, home_y_ = 0, away_x_ = 0;
  int64_t sum_ = 0, min_ = 0, max_ = 0;
  // Deviations from the first reading and their squares, summed in integers: nanometres of a
  // gauge's range square and sum well inside 64 bits for 64 readings, and need no FPU.
  int64_t first_ = 0, sum_deviation_ = 0, sum_squared_deviation_ = 0;
  bool failed_ = false;
  digitizer_Repeatability result_ = digitizer_Repeatability_init_zero;
};

}  // namespace dg
