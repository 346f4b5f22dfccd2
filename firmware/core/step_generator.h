// Two-axis step generator: straight-line moves (Bresenham) with a trapezoidal speed ramp,
// driven by the board's step timer interrupt.
#pragma once
#include <cstdint>

#include "common/status.h"
#include "firmware/hal/board.h"

namespace dg {

struct MotionConfig {
  uint32_t nm_per_step = 2500;         // 400 steps/mm: 1 mm lead screw, 200 steps, half stepping
  int32_t x_max_steps = 200 * 400;     // soft limits: travel from 0 (home) to max
  int32_t y_max_steps = 150 * 400;
  uint32_t max_rate_steps_s = 8000;    // 20 mm/s
  uint32_t accel_steps_s2 = 80000;     // 200 mm/s^2
  uint32_t dir_setup_ns = 5000;        // driver needs DIR stable this long before STEP
  // Homing (seek, latch, slow re-approach, pull-off), per axis towards its min switch.
  uint32_t home_seek_rate_steps_s = 4000;    // 10 mm/s
  uint32_t home_latch_rate_steps_s = 400;    // 1 mm/s: the switch is read at this speed
  int32_t home_backoff_steps = 800;          // 2 mm off the switch before the slow approach
  int32_t home_pull_off_steps = 400;         // 1 mm off the switch when homing ends
  int32_t home_switch_steps = -1;            // machine position where the min switch trips
  // Backlash compensation: motor steps taken, uncounted, when an axis reverses, so the table moves
  // as soon as the counted steps begin (a dial gauge reads to 1 um; lead-screw play is larger).
  // At power-up each axis is taken to have last moved positive.
  uint32_t backlash_x_steps = 0;
  uint32_t backlash_y_steps = 0;
};

// Why a move stopped before its end: an input seen asserted before a step.
enum class Trip : uint8_t { kNone, kLimitX, kLimitY, kEstop };

class StepGenerator {
 public:
  StepGenerator(hal::Board& board, const MotionConfig& config);

  // Starts a move to an absolute position in steps at up to `rate_steps_s`
  // (0 = the configured maximum). kBusy while moving; kInvalidArgument (soft
  // limit) when the target is outside the table, refused before any step.
  Status move_to(int32_t x_steps, int32_t y_steps, uint32_t rate_steps_s);
  bool busy() const { return busy_; }
  int32_t x_steps() const { return x_; }
  int32_t y_steps() const { return y_; }
  // A probing move: when the touch probe triggers, the position at that step is latched and the
  // table brakes to rest within `overtravel_steps` (the move is refused when the feed is too fast
  // to brake in that distance). touched() says whether it triggered.
  Status probe_to(int32_t x_steps, int32_t y_steps, uint32_t rate_steps_s, uint32_t overtravel_steps);
  bool touched() const { return touched_; }
  int32_t touch_x_steps() const { return touch_x_; }
  int32_t touch_y_steps() const { return touch_y_; }
  // A move without the soft limits, for homing: towards and past the table's ends.
  Status move_by_unchecked(int32_t dx_steps, int32_t dy_steps, uint32_t rate_steps_s);
  // Sets the current position without moving (after homing).
  void set_position(int32_t x_steps, int32_t y_steps);
  // Before every step the e-stop input and, moving towards min on an axis, that axis's limit
  // switch are read; one asserted on two reads kConfirmNs apart stops the move (no step is taken)
  // and is kept here.
  Trip trip() const { return trip_; }
  void clear_trip() {
    trip_ = Trip::kNone;
    estop_cut_ = false;
  }
  // The e-stop's hardware path: an edge interrupt on the e-stop input reads it again kConfirmNs
  // later and, still asserted, cuts the drivers at once and ends the move at its next tick (the
  // step interrupt's own reads stay, for a board without the edge). Called once at start.
  void attach_estop();
  // The touch probe's edge interrupt: the contacts opening latch the step counts at that moment;
  // the read before the next step confirms the stylus is still deflected (a kinematic probe stays
  // open while the table presses into it) and brakes, or drops the latch as a bounce. Without it
  // (a board with no edge) the read before each step latches alone. Called once at start.
  void attach_probe();
  // Stops at once (abort); the position stays exact.
  void stop();
  const MotionConfig& config() const { return config_; }
  // The delay between the two reads that confirm a safety input, ns.
  static constexpr uint32_t kConfirmNs = 20000;
  // Steps further apart than this are waited for in parts of it, each ending in a read of the e-stop.
  static constexpr uint32_t kSafetyReadNs = 250000;

 private:
  static uint32_t on_tick(void* self);
  static void on_estop_edge(void* self);
  static void on_probe_edge(void* self);
  uint32_t tick();
  Status start(int64_t dx, int64_t dy, uint32_t rate_steps_s);
  uint32_t period_ns(uint32_t step_index) const;
  // The timer's next delay towards a step `period` away (the first part of it when it is long).
  uint32_t until_next_step(uint32_t period);
  // Ends the move on a confirmed safety input: kept as trip(); the e-stop also cuts the drivers.
  // Returns the timer's 0 (stop).
  uint32_t halt(Trip trip);
  // Time from rest to step k at the configured acceleration, ns: ramp_ns_ * sqrt(k).
  uint64_t ramp_time_ns(uint32_t k) const;

  hal::Board& board_;
  MotionConfig config_;
  volatile int32_t x_ = 0;
  volatile int32_t y_ = 0;
  volatile bool busy_ = false;
  // Current move.
  int32_t step_x_ = 0, step_y_ = 0;  // +1 / -1 / 0 per axis
  uint32_t count_x_ = 0, count_y_ = 0, total_ = 0, done_ = 0;
  int64_t error_ = 0;
  uint32_t rate_ = 0;
  uint64_t ramp_ns_ = 0;  // 1e9 * sqrt(2 / a): the time to the first step from rest
  uint32_t stop_at_ = 0;  // the step the move ends on (total_, or sooner after a touch)
  bool probing_ = false;
  volatile bool touched_ = false;
  volatile bool touch_edge_ = false;  // the probe's edge latched touch_x_ and touch_y_; the tick brakes
  volatile int32_t touch_x_ = 0, touch_y_ = 0;
  volatile Trip trip_ = Trip::kNone;
  // A safety input was seen asserted on the last tick and is read again on this one.
  bool confirming_ = false;
  // The e-stop's edge interrupt cut the drivers: the next tick ends the move, taking no step.
  volatile bool estop_cut_ = false;
  uint32_t wait_left_ns_ = 0;  // of the wait for the next step, after the current part
  // The way each axis last moved; at power-up taken as positive, as homing's pull-off leaves it.
  int8_t last_dir_x_ = 1, last_dir_y_ = 1;
  uint32_t takeup_x_ = 0, takeup_y_ = 0;    // backlash steps still to take before this move
};

// Integer square root (floor) for the speed ramp: no FPU needed.
uint32_t isqrt64(uint64_t value);

}  // namespace dg
