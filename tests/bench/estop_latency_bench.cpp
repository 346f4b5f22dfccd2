// How long after the e-stop input opens the drivers are switched off, in the simulator's virtual
// time: the step interrupt reads the input before each step and confirms it 20 us later, so the
// latency is the wait for the next step plus the confirmation; slowest at the start of a move,
// where the ramp's first steps are milliseconds apart.
#include <algorithm>
#include <cstdio>
#include <vector>

#include "firmware/core/step_generator.h"
#include "hw/sim/sim_board.h"

int main() {
  std::printf("e-stop to drivers off, a 10 mm x move from rest at 20 mm/s and 200 mm/s^2, pressed at:\n");
  std::vector<double> latencies_us;
  for (uint64_t press_us = 100; press_us <= 600000; press_us = press_us * 3 / 2 + 37) {
    dg::sim::SimConfig c;
    c.estop_at_ns = press_us * 1000;
    c.estop_for_ns = 1000000000;
    dg::sim::SimBoard board(c, nullptr);
    dg::StepGenerator motion(board, dg::MotionConfig{});
    if (motion.move_to(4000, 0, 0) != dg::Status::kOk) return 1;
    while (motion.busy() && board.wait(UINT64_MAX)) {
    }
    if (board.drivers_on()) continue;  // the move ended before the press
    const double latency_us = static_cast<double>(board.drivers_cut_ns() - c.estop_at_ns) * 1e-3;
    latencies_us.push_back(latency_us);
    std::printf("  %8.1f ms into the move: %7.1f us\n", press_us * 1e-3, latency_us);
  }
  std::sort(latencies_us.begin(), latencies_us.end());
  if (latencies_us.empty()) return 1;
  std::printf("worst %.1f us, median %.1f us over %zu presses (target of a hardware path: 50 us)\n", latencies_us.back(),
              latencies_us[latencies_us.size() / 2], latencies_us.size());
  return 0;
}
