// Scan time against its lower bound: a 41 x 31 serpentine grid at 1 mm on the simulated table,
// timed in virtual time, against the sum of each move's shortest time under the motion profile
// (trapezoid or triangle at the configured feed and acceleration) and each reading's gauge time.
#include <cmath>
#include <cstdio>
#include <vector>

#include "firmware/core/digimatic_reader.h"
#include "firmware/core/scan_engine.h"
#include "hw/sim/sim_board.h"
#include "tests/support/scan_request.h"

namespace {

struct Count final : dg::PointSink {
  bool accept(const dg::PointSample&) override {
    ++points;
    return true;
  }
  int points = 0;
};

// Shortest time to move `steps` from rest to rest at up to `rate` steps/s with acceleration `a`.
double move_seconds(double steps, double rate, double a) {
  if (steps <= 0) return 0;
  if (steps >= rate * rate / a) return steps / rate + rate / a;
  return 2 * std::sqrt(steps / a);
}

}  // namespace

int main() {
  dg::sim::SimConfig sim;
  sim.part.kind = dg::sim::PartKind::kDome;
  dg::sim::SimBoard board(sim, nullptr);
  const dg::MotionConfig motion_config;
  dg::StepGenerator motion(board, motion_config);
  dg::DigimaticTiming timing;
  timing.first_clock_timeout_us = 200000;
  dg::DigimaticReader gauge(board, timing);
  gauge.attach();
  dg::ScanEngine scan(board, motion, gauge, dg::ScanLimits{});
  digitizer_ScanRequest r = dg::test::grid_request(1, 0, 40000000, 30000000, 1000000, digitizer_ScanPattern_PATTERN_SERPENTINE);
  const char* reason = "";
  if (scan.start(r, 1, 10000, &reason) != digitizer_FaultCode_FAULT_NONE) {
    std::printf("scan refused: %s\n", reason);
    return 1;
  }
  Count sink;
  while (!scan.finished()) {
    scan.poll(sink);
    if (!scan.finished() && !board.wait(scan.deadline_us())) break;
  }
  const double measured = static_cast<double>(scan.duration_us()) * 1e-6;
  // The bound: every move at the requested feed (capped by the axes' maximum), every reading the
  // gauge's own time.
  const double per = motion_config.nm_per_step;
  double rate = r.feed_um_s * 1000.0 / per;
  if (rate > motion_config.max_rate_steps_s) rate = motion_config.max_rate_steps_s;
  const double a = motion_config.accel_steps_s2;
  const double step = r.step_x_nm / per, cross = r.step_y_nm / per;
  const int nx = 41, ny = 31;
  double bound = (ny * (nx - 1)) * move_seconds(step, rate, a) + (ny - 1) * move_seconds(cross, rate, a);
  // A reading ends at the 52nd rising edge: REQ to the first clock, 52 low and 51 high phases.
  const double reading =
      (sim.gauge.request_to_clock_us + 52.0 * sim.gauge.clock_low_us + 51.0 * sim.gauge.clock_high_us) * 1e-6;
  bound += nx * ny * reading;
  std::printf("41 x 31 serpentine at 1 mm, %.0f mm/s: %d points in %.2f s of table time; lower bound %.2f s "
              "(moves at the profile's limits plus %.1f ms a reading): %.3fx\n",
              r.feed_um_s / 1000.0, sink.points, measured, bound, reading * 1e3, measured / bound);
  return sink.points == nx * ny ? 0 : 1;
}
