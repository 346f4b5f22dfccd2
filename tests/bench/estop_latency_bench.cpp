// How long after the e-stop input opens the drivers are switched off, in the simulator's virtual
// time, by each of the firmware's two paths: the step interrupt reads the input before each step
// (and every 250 us between steps far apart) and confirms it 20 us later; the e-stop's edge
// interrupt confirms it 20 us after the edge and cuts the drivers at once. Slowest at the start of
// a move, where the ramp's first steps are milliseconds apart. Then the edge path once more through
// the STM32F411 board's own code on the register-level fake of its chip, in the chip's cycles.
#include <algorithm>
#include <cstdio>
#include <vector>

#include "firmware/core/step_generator.h"
#include "hw/sim/sim_board.h"
#include "tests/support/black_pill.h"

namespace {

// Presses during a 10 mm x move from rest; the worst and median latency, us. False when no press
// landed during the move.
bool measure(bool edge, double* worst_us, double* median_us, size_t* presses) {
  std::vector<double> latencies_us;
  for (uint64_t press_us = 100; press_us <= 600000; press_us = press_us * 3 / 2 + 37) {
    dg::sim::SimConfig c;
    c.estop_at_ns = press_us * 1000;
    c.estop_for_ns = 1000000000;
    dg::sim::SimBoard board(c, nullptr);
    dg::StepGenerator motion(board, dg::MotionConfig{});
    if (edge) motion.attach_estop();
    if (motion.move_to(4000, 0, 0) != dg::Status::kOk) return false;
    while (motion.busy() && board.wait(UINT64_MAX)) {
    }
    if (board.drivers_on()) continue;  // the move ended before the press
    latencies_us.push_back(static_cast<double>(board.drivers_cut_ns() - c.estop_at_ns) * 1e-3);
  }
  if (latencies_us.empty()) return false;
  std::sort(latencies_us.begin(), latencies_us.end());
  *worst_us = latencies_us.back();
  *median_us = latencies_us[latencies_us.size() / 2];
  *presses = latencies_us.size();
  return true;
}

// The same presses through the Black Pill's own board code on the register-level fake of its chip
// (EXTI15_10, the DWT-timed confirming read, the enable pin's BSRR write), in the chip's cycles.
bool measure_on_black_pill(double* worst_us, double* median_us, size_t* presses) {
  using dg::hal::Pin;
  constexpr uint64_t kCyclesPerUs = dg::test::FakeStm32::kCoreHz / 1000000;
  std::vector<double> latencies_us;
  for (uint64_t press_us = 100; press_us <= 600000; press_us = press_us * 3 / 2 + 37) {
    dg::test::BlackPill pill;
    pill.drive(Pin::kEstop, false);
    pill.drive(Pin::kLimitXMin, false);
    pill.drive(Pin::kLimitYMin, false);
    dg::StepGenerator motion(pill.board, dg::MotionConfig{});
    motion.attach_estop();
    const uint64_t pressed = pill.chip.cycles() + press_us * kCyclesPerUs;
    pill.chip.at(pressed, [&pill] { pill.drive(Pin::kEstop, true); });
    if (motion.move_to(4000, 0, 0) != dg::Status::kOk) return false;
    while (motion.busy()) pill.chip.run_for(100 * kCyclesPerUs);
    pill.chip.run_for(press_us * kCyclesPerUs);
    const uint64_t cut = pill.drivers_cut_at(pressed);
    if (cut == 0) continue;  // the move ended before the press
    latencies_us.push_back(static_cast<double>(cut - pressed) / kCyclesPerUs);
  }
  if (latencies_us.empty()) return false;
  std::sort(latencies_us.begin(), latencies_us.end());
  *worst_us = latencies_us.back();
  *median_us = latencies_us[latencies_us.size() / 2];
  *presses = latencies_us.size();
  return true;
}

}  // namespace

int main() {
  std::printf("e-stop to drivers off, a 10 mm x move from rest at 20 mm/s and 200 mm/s^2 (target 50 us):\n");
  for (bool edge : {false, true}) {
    double worst = 0, median = 0;
    size_t presses = 0;
    if (!measure(edge, &worst, &median, &presses)) return 1;
    std::printf("  %-44s worst %6.1f us, median %6.1f us over %zu presses\n",
                edge ? "the edge interrupt (the firmware's path):" : "the step interrupt's reads alone:", worst, median,
                presses);
  }
  double worst = 0, median = 0;
  size_t presses = 0;
  if (!measure_on_black_pill(&worst, &median, &presses)) return 1;
  std::printf("  %-44s worst %6.1f us, median %6.1f us over %zu presses\n",
              "the Black Pill's board code (register fake):", worst, median, presses);
  return 0;
}
