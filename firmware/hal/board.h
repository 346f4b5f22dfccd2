// The hardware abstraction the firmware core runs on: pins, edges, step timer, clock, byte link.
// A board (real or simulated) implements this once; the core never sees registers.
#pragma once
#include <cstddef>
#include <cstdint>

namespace dg::hal {

// Logical pins. Levels are logical (true = asserted); a board maps them to its
// electrical polarity (the Digimatic REQ line, for example, is active low).
enum class Pin : uint8_t {
  kStepX,
  kDirX,  // true = towards +x
  kStepY,
  kDirY,  // true = towards +y
  kGaugeReq,
  kGaugeClock,
  kGaugeData,
  kLimitXMin,
  kLimitYMin,
  kEstop,
  kTouchProbe,  // true = the stylus is deflected (touch-trigger probe)
  kCount,
};

// Why a board last started, from its reset flags.
enum class ResetCause : uint8_t { kUnknown, kPowerOn, kPin, kWatchdog, kSoftware, kBrownOut };

using EdgeHandler = void (*)(void* context);
// Returns the delay to the next call in nanoseconds, or 0 to stop the timer.
using TimerHandler = uint32_t (*)(void* context);

class Board {
 public:
  virtual ~Board() = default;

  virtual void write_pin(Pin pin, bool level) = 0;
  virtual bool read_pin(Pin pin) = 0;

  // The stepper drivers' enable line: off, the motors carry no current and steps do nothing.
  // Boards power up with the drivers on; the core turns them off in alarm.
  virtual void enable_drivers(bool on) = 0;

  // Calls `handler` from interrupt context on each rising edge of `pin`.
  virtual void on_rising_edge(Pin pin, EdgeHandler handler, void* context) = 0;

  // One-shot-chained timer for step generation: first call after `delay_ns`,
  // then after whatever the handler returns.
  virtual void start_step_timer(uint32_t delay_ns, TimerHandler handler, void* context) = 0;
  virtual void stop_step_timer() = 0;

  // Monotonic device time.
  virtual uint64_t now_us() = 0;

  // Busy-waits about `ns` (an interrupt's short, bounded wait: a safety input's confirming read).
  // A board with a finer clock than now_us() overrides it.
  virtual void spin_ns(uint32_t ns) {
    const uint64_t until = now_us() + (ns + 999) / 1000;
    while (now_us() < until) {
    }
  }

  // Non-blocking byte link to the host: returns how many bytes were taken/read.
  virtual size_t link_write(const uint8_t* data, size_t size) = 0;
  virtual size_t link_read(uint8_t* data, size_t capacity) = 0;

  // Whether the host has suspended the link (USB suspend: the bus idle for 3 ms, a host going to
  // sleep). A board whose link cannot be suspended says false.
  virtual bool link_suspended() { return false; }

  // Sleeps until an interrupt fires, a byte arrives or `deadline_us` passes
  // (UINT64_MAX: no deadline). Returns false when the board must shut down.
  virtual bool wait(uint64_t deadline_us) = 0;

  // The independent watchdog: once started it resets the board unless kicked again within
  // `timeout_ms`, asleep or not, and nothing but a reset stops it. A board without one ignores both.
  virtual void watchdog_start(uint32_t timeout_ms) { (void)timeout_ms; }
  virtual void watchdog_kick() {}
  virtual ResetCause reset_cause() { return ResetCause::kUnknown; }

  // A few bytes of settings kept through a power-off (the calibration's summary), where the board
  // has somewhere to keep them: store returns false when it has not (the device then holds them
  // until reset), load how many bytes it read (0: none stored).
  virtual bool store_settings(const uint8_t* data, size_t size) {
    (void)data, (void)size;
    return false;
  }
  virtual size_t load_settings(uint8_t* data, size_t capacity) {
    (void)data, (void)capacity;
    return 0;
  }
};

}  // namespace dg::hal
