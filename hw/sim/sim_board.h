// The simulated board: a virtual-time machine with two stepper axes, a Digimatic gauge
// over a virtual part, and a byte link to the host. Implements the firmware HAL.
#pragma once
#include <cstddef>
#include <climits>
#include <cstdint>
#include <vector>

#include "firmware/hal/board.h"
#include "firmware/hal/link_port.h"
#include "hw/sim/caliper_gauge.h"
#include "hw/sim/digimatic_gauge.h"
#include "hw/sim/machine_errors.h"
#include "hw/sim/parts.h"

namespace dg::sim {

using hal::LinkPort;


// How the simulated min switches are wired.
enum class SwitchWiring : uint8_t {
  kNormallyClosed,  // as documented: the circuit opens when the table presses the switch
  kOpen,            // not wired (or a connector off): the circuit is always open
  kStuckClosed,     // a jammed switch or a shorted cable: the circuit never opens
};

struct SimConfig {
  Part part{};
  GaugeConfig gauge{};
  uint64_t seed = 1;
  uint32_t nm_per_step = 2500;
  // The table starts here (steps); the part sits with its corner at table (0, 0).
  int32_t start_x_steps = 0;
  int32_t start_y_steps = 0;
  // The min limit switches trip below table 0; the table hits its mechanical stop this far below
  // (steps towards it are lost, as a stalled motor loses them).
  int32_t hard_stop_steps = -800;
  // The min switches are normally closed, as the docs wire them: the input reads "tripped" whenever
  // the circuit is open, so a switch that is pressed, unplugged or has a cut wire all read tripped.
  SwitchWiring switches = SwitchWiring::kNormallyClosed;
  // After the table crosses a switch's edge its contacts chatter this long (0: clean contacts).
  uint64_t switch_bounce_ns = 0;
  // From this virtual time the x switch's wire is cut, so it reads tripped (0: never).
  uint64_t x_wire_cut_at_ns = 0;
  // Electrical noise: a 2 us spike on the limit and e-stop inputs every this long (0: none).
  uint64_t glitch_period_ns = 0;
  // The fastest the gauge's plunger falls after a part that drops away beneath it, mm/s (its
  // spring against its own mass and friction); rising, the part pushes it. 0: it follows at once.
  double plunger_mm_s = 0;
  bool caliper = false;        // the gauge port carries a 24-bit caliper instead of a Digimatic gauge
  // A touch-trigger probe's stylus meets a face at table x >= touch_x_steps (or y >= touch_y_steps);
  // INT32_MAX: no face.
  int32_t touch_x_steps = INT32_MAX;
  int32_t touch_y_steps = INT32_MAX;
  // Lead-screw play, motor steps per axis: after a reversal the table stays put this long.
  int32_t backlash_steps = 0;
  // The machine's own errors (squareness, scale, the travel's flatness, drift); none by default.
  MachineErrors machine{};
  // The e-stop input is asserted from this virtual time for this long (0: never).
  uint64_t estop_at_ns = 0;
  uint64_t estop_for_ns = 0;
  // The firmware's main loop hangs at this virtual time (0: never): it stops coming back, as a
  // loop stuck on a dead peripheral would, until the watchdog (if started) resets the board.
  uint64_t hang_at_ns = 0;
};

class SimBoard final : public hal::Board {
 public:
  SimBoard(const SimConfig& config, LinkPort* link);
  // A real-time clock in milliseconds (a host program has one; the emulated board does not).
  // With it, a firmware deadline that waits for the host runs out after 250 ms of real time
  // however much the host says meanwhile; without it, only after 250 ms of host silence.
  void set_real_clock(uint64_t (*now_ms)()) { real_ms_ = now_ms; }

  void write_pin(hal::Pin pin, bool level) override;
  bool read_pin(hal::Pin pin) override;
  void enable_drivers(bool on) override {
    if (drivers_on_ && !on) drivers_cut_ns_ = now_ns_;
    drivers_on_ = on;
  }
  void on_rising_edge(hal::Pin pin, hal::EdgeHandler handler, void* context) override;
  void start_step_timer(uint32_t delay_ns, hal::TimerHandler handler, void* context) override;
  void stop_step_timer() override;
  uint64_t now_us() override { return now_ns_ / 1000; }
  // Virtual time passes; the step timer, whose interrupt outranks the edge interrupts that spin,
  // keeps firing meanwhile.
  void spin_ns(uint32_t ns) override;
  size_t link_write(const uint8_t* data, size_t size) override;
  size_t link_read(uint8_t* data, size_t capacity) override;
  bool link_suspended() override { return link_suspended_; }
  // The host suspends the link (a laptop going to sleep) or resumes it.
  void set_link_suspended(bool suspended) { link_suspended_ = suspended; }
  bool wait(uint64_t deadline_us) override;
  // The MCU's independent watchdog: it runs in virtual time, asleep or not; missed, it resets the
  // board (wait() returns false and reset_pending() says so).
  void watchdog_start(uint32_t timeout_ms) override;
  void watchdog_kick() override;
  hal::ResetCause reset_cause() override { return reset_cause_; }
  // The MCU's settings flash: kept through a watchdog reset (the same SimBoard), and, where the
  // simulator program keeps a file of it, through a restart: preload_settings() puts the file's
  // bytes in at power-up and the hook keeps every store (true: kept). Without a hook, a store says
  // it is not kept through a power-off, which is the truth for a simulator that ends.
  bool store_settings(const uint8_t* data, size_t size) override;
  size_t load_settings(uint8_t* data, size_t capacity) override;
  void preload_settings(const uint8_t* data, size_t size) { store_bytes(data, size); }
  void on_settings_stored(bool (*hook)(const uint8_t* data, size_t size, void* context), void* context) {
    settings_hook_ = hook, settings_context_ = context;
  }
  // The watchdog reset the board: the firmware starts again from scratch (its RAM is gone), while
  // the table, the part and the gauge stay as they are. Clears the flag.
  bool take_reset();

  // Inspection for tests and the simulator's report.
  uint64_t now_ns() const { return now_ns_; }
  int64_t table_x_steps() const { return x_steps_; }
  int64_t table_y_steps() const { return y_steps_; }
  double table_x_mm() const { return static_cast<double>(x_steps_) * (config_.nm_per_step * 1e-6); }
  double table_y_mm() const { return static_cast<double>(y_steps_) * (config_.nm_per_step * 1e-6); }
  // What the gauge reads: the part where the table really is, plus the travel's height error
  // where the carriage is commanded, plus the stand's drift.
  double height_under_probe_mm() const;
  // Where the plunger is now: on the part, or above it and falling after it (plunger_mm_s).
  double plunger_mm();
  const DigimaticGauge& gauge() const { return gauge_; }
  uint64_t step_count() const { return steps_; }
  // Tests: the virtual time of every x step is appended here (null: not kept).
  void log_x_steps(std::vector<uint64_t>* log) { x_step_log_ = log; }
  // Steps the drivers were given against the mechanical stop (lost).
  uint64_t lost_steps() const { return lost_steps_; }
  bool drivers_on() const { return drivers_on_; }
  // When the drivers were last switched off (virtual ns; 0: never).
  uint64_t drivers_cut_ns() const { return drivers_cut_ns_; }
  // Step pulses given while the drivers were off (the motors did not turn).
  uint64_t steps_without_drivers() const { return steps_without_drivers_; }
  // Tests: the x switch's wire is cut at this virtual time.
  void cut_x_wire_at(uint64_t t_ns) { config_.x_wire_cut_at_ns = t_ns; }
  // Shortest time between two steps on one axis seen so far, in ns.
  uint64_t min_step_interval_ns() const { return min_step_interval_ns_; }

 private:
  static constexpr uint64_t kNever = UINT64_MAX;
  // The link is looked at once per USB full-speed frame of virtual time.
  static constexpr uint64_t kLinkPollNs = 1000000;

  void step_axis(int axis);
  // The plunger falls towards the part under it at plunger_mm_s; call before the table moves.
  void track_plunger();
  double plunger_at_mm_ = 0;
  uint64_t plunger_ns_ = 0;
  bool plunger_known_ = false;
  bool limit_tripped(int axis) const;
  bool glitch() const;

  SimConfig config_;
  double flatness_peak_ = 1;  // of config_.machine's map (flatness_map_peak)
  LinkPort* link_;
  DigimaticGauge gauge_;
  CaliperGauge caliper_;
  uint64_t gauge_event_ns() const { return config_.caliper ? caliper_.next_event_ns() : gauge_.next_event_ns(); }
  // The next rising edge of the e-stop input after now (the press, or a spike if `spikes`; kNever: none).
  uint64_t estop_edge_ns(bool spikes) const;
  // Runs the step timer's interrupts due up to `until_ns`.
  void run_timer_until(uint64_t until_ns);
  hal::EdgeHandler estop_handler_ = nullptr;
  void* estop_context_ = nullptr;
  uint64_t now_ns_ = 0;
  bool pins_[static_cast<int>(hal::Pin::kCount)] = {};
  hal::EdgeHandler clock_handler_ = nullptr;
  void* clock_context_ = nullptr;
  // The touch probe's edge: a step that brings the stylus onto the face raises it, and it is taken
  // when the step interrupt (which outranks it) returns.
  hal::EdgeHandler touch_handler_ = nullptr;
  void* touch_context_ = nullptr;
  bool touch_edge_due_ = false;
  bool link_suspended_ = false;
  bool touching() const { return x_steps_ >= config_.touch_x_steps || y_steps_ >= config_.touch_y_steps; }
  void take_touch_edge();
  // Runs the step interrupt due now, schedules the next one; returns its delay (0: the move ended).
  uint32_t fire_step_timer();
  hal::TimerHandler timer_handler_ = nullptr;
  void* timer_context_ = nullptr;
  uint64_t timer_next_ns_ = kNever;
  int64_t x_steps_ = 0, y_steps_ = 0;
  int64_t motor_[2] = {0, 0};  // where the motors have turned the screws to (equals the table without play)
  uint64_t lost_steps_ = 0;
  bool drivers_on_ = true;
  uint64_t drivers_cut_ns_ = 0;
  uint64_t steps_without_drivers_ = 0;
  std::vector<uint64_t>* x_step_log_ = nullptr;
  uint64_t last_step_ns_[2] = {kNever, kNever};
  uint64_t switch_edge_ns_[2] = {kNever, kNever};  // when the table last crossed each switch's edge
  uint64_t min_step_interval_ns_ = kNever;
  // The watchdog (kNever: not started) and the reset it caused.
  uint64_t watchdog_timeout_ns_ = kNever;
  uint64_t watchdog_kicked_ns_ = 0;
  bool hung_ = false;  // the main loop hung (once, at config_.hang_at_ns)
  bool reset_pending_ = false;
  hal::ResetCause reset_cause_ = hal::ResetCause::kPowerOn;
  bool store_bytes(const uint8_t* data, size_t size);
  uint8_t settings_[64] = {};
  size_t settings_size_ = 0;
  bool (*settings_hook_)(const uint8_t*, size_t, void*) = nullptr;
  void* settings_context_ = nullptr;
  uint64_t steps_ = 0;
  uint64_t last_link_poll_ns_ = 0;
  bool link_hint_ = true;
  // The firmware's deadline that virtual time is standing still for, and since when (real ms).
  uint64_t stalled_deadline_ns_ = 0;
  uint64_t stalled_since_ms_ = 0;
  uint64_t (*real_ms_)() = nullptr;
};

}  // namespace dg::sim
