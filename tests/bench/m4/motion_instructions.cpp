// Instructions per step interrupt and per gauge reading of the firmware core, counted on QEMU's
// Cortex-M4 (mps2-an386) under -icount like the fit benchmark: the step generator's tick (two-axis
// Bresenham, the trapezoid's integer square roots, the safety inputs) and a Digimatic frame's
// 52 clock interrupts plus its decode, through a board whose pins are plain memory.
#include <cstdint>

#include "firmware/core/digimatic.h"
#include "firmware/core/digimatic_reader.h"
#include "firmware/core/step_generator.h"
#include "hw/boards/qemu-mps2/semihosting.h"
#include "tests/bench/m4/ticks.h"

namespace {

// A board of memory cells: what remains is the firmware's own work.
class MemoryBoard final : public dg::hal::Board {
 public:
  void write_pin(dg::hal::Pin pin, bool level) override {
    if (pin == dg::hal::Pin::kStepX && level && !pins[static_cast<int>(pin)]) ++x_steps;
    pins[static_cast<int>(pin)] = level;
  }
  volatile uint32_t x_steps = 0;
  bool read_pin(dg::hal::Pin pin) override { return pins[static_cast<int>(pin)]; }
  void enable_drivers(bool on) override { drivers_on = on; }
  volatile bool drivers_on = true;
  void on_rising_edge(dg::hal::Pin, dg::hal::EdgeHandler h, void* c) override {
    edge = h;
    edge_context = c;
  }
  void start_step_timer(uint32_t, dg::hal::TimerHandler h, void* c) override {
    timer = h;
    timer_context = c;
  }
  void stop_step_timer() override { timer = nullptr; }
  uint64_t now_us() override { return now; }
  size_t link_write(const uint8_t*, size_t size) override { return size; }
  size_t link_read(uint8_t*, size_t) override { return 0; }
  bool wait(uint64_t) override { return true; }

  volatile bool pins[static_cast<int>(dg::hal::Pin::kCount)] = {};
  dg::hal::EdgeHandler edge = nullptr;
  void* edge_context = nullptr;
  dg::hal::TimerHandler timer = nullptr;
  void* timer_context = nullptr;
  uint64_t now = 0;
};


void report(const char* what, uint64_t value) {
  dg::bench::write_text(what);
  dg::bench::write_number(value);
  dg::bench::write_text("\n");
}

}  // namespace

int main() {
  // Locals, not statics: the bare-metal image registers no destructors.
  MemoryBoard board;
  const uint64_t milli_per_tick = dg::bench::milli_instructions_per_tick();

  // 6000 steps along x with 2000 along y: ramps up, cruises, ramps down.
  dg::MotionConfig config;
  dg::StepGenerator motion(board, config);
  motion.move_to(6000, 2000, 0);
  // Interrupts include the wakes between steps more than 250 us apart that only read the e-stop.
  uint32_t ticks = 0, interrupts = 0;
  dg::bench::start_ticks();
  while (board.timer != nullptr && interrupts < 200000) {
    const uint32_t next = board.timer(board.timer_context);
    ++interrupts;
    if (next == 0) break;
  }
  ticks = dg::bench::ticks_since_start();
  const uint32_t steps = board.x_steps;
  const uint64_t per_step = (ticks * milli_per_tick / 1000 + steps / 2) / steps;
  const uint64_t per_interrupt = (ticks * milli_per_tick / 1000 + interrupts / 2) / interrupts;

  // A Digimatic frame of 12.345 mm: 52 clock interrupts sampling DATA, then poll() decodes.
  dg::DigimaticReading value;
  value.value = 12345;
  value.decimals = 3;
  dg::DigimaticBits frame;
  dg::digimatic_encode(value, &frame);
  dg::DigimaticReader reader(board, dg::DigimaticTiming{});
  reader.attach();
  constexpr int kFrames = 200;
  int good = 0;
  dg::bench::start_ticks();
  for (int f = 0; f < kFrames; ++f) {
    reader.start();
    for (int bit = 0; bit < dg::kDigimaticBits; ++bit) {
      board.pins[static_cast<int>(dg::hal::Pin::kGaugeData)] = (frame.digit[bit / 4] >> (bit % 4)) & 1u;
      board.edge(board.edge_context);
    }
    if (reader.poll() == dg::Probe::State::kDone && reader.value_nm() == 12345000) ++good;
  }
  const uint64_t per_frame = (dg::bench::ticks_since_start() * milli_per_tick / 1000 + kFrames / 2) / kFrames;

  dg::bench::write_text(dg::bench::kCoreName);
  dg::bench::write_text(", the firmware core's interrupts:\n");
  report("  instructions per step (StepGenerator ticks: a ramped move of 6000 x and 2000 y steps): ", per_step);
  report("  instructions per step-timer interrupt (steps and the e-stop reads between slow steps): ", per_interrupt);
  // At 96 MHz (the STM32F411 board), counting an instruction as about 1.3 cycles plus 30 cycles of
  // interrupt entry and exit.
  report("  highest step rate the tick sustains at 96 MHz, steps/s (estimate): ", 96000000ull * 10 / (per_step * 13 + 300));
  report("  instructions per Digimatic reading (52 clock interrupts and the decode): ", per_frame);
  dg::bench::write_text(good == kFrames && steps == 6000 ? "  readings and steps: ok\n" : "  readings and steps: FAILED\n");
  return good == kFrames && steps == 6000 ? 0 : 1;
}
