// Scanning on the fly against stop-and-go, in virtual time on the simulated table: the table time
// of 40 x 30 mm with lines 1 mm apart, and every point's error against the part's true shape after
// the host's latch-delay correction, with a gauge that latches 3 ms (sigma 0.1 ms) after REQ (a
// quicker one 0.6 ms).
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "firmware/core/digimatic_reader.h"
#include "firmware/core/scan_engine.h"
#include "host/scan/fly_correction.h"
#include "hw/sim/sim_board.h"
#include "tests/support/collect_points.h"
#include "tests/support/scan_request.h"

namespace {

struct Run {
  double table_s = 0;
  double latch_ms = 0;  // the simulated gauge's true latch delay
  std::vector<dg::PointSample> points;
  digitizer_ScanRequest request{};
};

// The simulator's default Digimatic (5 ms to the first clock, 0.4 ms a bit: 25.8 ms a reading), or
// one as quick as Mitutoyo's ID-H states (T1 0.7..1.2 ms; 0.3..0.5 ms a bit): 1 ms and 0.35 ms.
Run scan(dg::sim::PartKind part, bool fly, double step_x_mm, double noise_um, double plunger_mm_s, bool quick_gauge = false) {
  dg::sim::SimConfig sim;
  sim.gauge.latch_delay_us = 3000;
  if (quick_gauge) {
    sim.gauge.request_to_clock_us = 1000;
    sim.gauge.clock_low_us = 200;
    sim.gauge.clock_high_us = 150;
    sim.gauge.latch_delay_us = 600;  // it latches before its first clock
  }
  sim.part.kind = part;
  sim.seed = 11;
  sim.gauge.noise_sigma_mm = noise_um * 1e-3;
  sim.gauge.latch_jitter_us = 100;
  sim.plunger_mm_s = plunger_mm_s;
  dg::sim::SimBoard board(sim, nullptr);
  dg::StepGenerator motion(board, dg::MotionConfig{});
  dg::DigimaticTiming timing;
  timing.first_clock_timeout_us = 200000;
  dg::DigimaticReader gauge(board, timing);
  gauge.attach();
  dg::ScanEngine engine(board, motion, gauge, dg::ScanLimits{});
  Run run;
  run.request = dg::test::grid_request(1, 0, 40000000, 30000000, 1000000, digitizer_ScanPattern_PATTERN_SERPENTINE);
  run.request.step_x_nm = static_cast<uint32_t>(std::lround(step_x_mm * 1e6));
  if (fly) {
    run.request.mode = digitizer_ScanMode_SCAN_MODE_FLY;
    run.request.feed_um_s = 0;
    run.request.plunger_follow_um_s = static_cast<uint32_t>(plunger_mm_s * 1000);
  }
  const char* reason = "";
  if (engine.start(run.request, 1, 10000, &reason) != digitizer_FaultCode_FAULT_NONE) throw std::runtime_error(reason);
  dg::test::CollectPoints sink;
  while (!engine.finished()) {
    engine.poll(sink);
    if (!engine.finished() && !board.wait(engine.deadline_us())) break;
  }
  run.table_s = static_cast<double>(engine.duration_us()) * 1e-6;
  run.latch_ms = sim.gauge.latch_delay_us * 1e-3;
  run.points = std::move(sink.points);
  return run;
}

// The fly scan corrected as the host reads it; its points' worst and RMS error against the part.
void report(const char* name, dg::sim::PartKind kind, double noise_um, double plunger_mm_s, double stop_s,
            bool quick_gauge = false) {
  Run fly = scan(kind, true, 0.2, noise_um, plunger_mm_s, quick_gauge);
  dg::host::ScanData data;
  data.request = fly.request;
  data.points = fly.points;
  const auto fix = dg::host::correct_fly_scan(data, nullptr, name);
  dg::sim::Part part;
  part.kind = kind;
  double worst_um = 0, sum_sq = 0;
  for (const auto& p : data.points) {
    const double e_um = (p.z_nm * 1e-6 - part.height_mm(p.x_nm * 1e-6, p.y_nm * 1e-6)) * 1e3;
    worst_um = std::fmax(worst_um, std::fabs(e_um));
    sum_sq += e_um * e_um;
  }
  const double rms_um = std::sqrt(sum_sq / static_cast<double>(data.points.size()));
  std::printf("%-9s noise %.0f um: %zu points in %.1f s of table time (%.3fx the 1 mm stop-and-go grid's %.1f s), a point "
              "every %.3f mm at %.2f mm/s; latch delay %.3f ms (u %.3f; true %.3f); after it: worst %.2f um, RMS %.2f um",
              name, noise_um, fly.points.size(), fly.table_s, fly.table_s / stop_s, stop_s, fix->spacing_mm, fix->feed_mm_s,
              fix->latch_delay_ms, fix->u_latch_delay_ms, fly.latch_ms, worst_um, rms_um);
  if (fix->lifted > 0) std::printf("; %zu lifted readings left out on %zu lines", fix->lifted, fix->lifted_lines.size());
  std::printf("\n");
}

}  // namespace

int main() {
  try {
    const double stop_s = scan(dg::sim::PartKind::kSaddle, false, 1.0, 0, 0).table_s;
    const Run coarse = scan(dg::sim::PartKind::kSaddle, true, 1.0, 0, 0);
    std::printf("stop-and-go 41 x 31 at 1 mm: %.1f s of table time; on the fly, a point every 1 mm or closer: %.1f s "
                "(%.3fx, %zu points; the axes' 20 mm/s caps the feed)\n",
                stop_s, coarse.table_s, coarse.table_s / stop_s, coarse.points.size());
    std::printf("on the fly, lines 1 mm apart, a point every 0.2 mm or closer (the Digimatic's 25.8 ms cycle sets the "
                "feed); target 0.2x of stop-and-go, every point within 2 um + the gauge's noise:\n");
    report("saddle", dg::sim::PartKind::kSaddle, 0, 0, stop_s);
    report("saddle", dg::sim::PartKind::kSaddle, 1, 0, stop_s);
    report("canister", dg::sim::PartKind::kCanister, 0, 0, stop_s);
    report("canister", dg::sim::PartKind::kCanister, 1, 0, stop_s);
    report("dome", dg::sim::PartKind::kDome, 1, 5, stop_s);
    std::printf("the same with a gauge as quick as Mitutoyo's ID-H states (1 ms to the first clock, 0.35 ms a bit: 19.2 ms a "
                "reading):\n");
    report("canister", dg::sim::PartKind::kCanister, 1, 0, stop_s, true);
    std::printf("(0.2x of stop-and-go with a point every 0.2 mm needs about 150 readings a second: no Digimatic gauge gives "
                "that; the fly scan's table time is the gauge's cycle times the points)\n");
  } catch (const std::exception& e) {
    std::printf("fly scan bench failed: %s\n", e.what());
    return 1;
  }
  return 0;
}
