// Instructions per point of the device's fixed-point streaming fit, counted on QEMU's Cortex-M4
// (mps2-an386) run with -icount: SysTick ticks are calibrated against a loop of known length, so
// the figures do not depend on the board's clock. Prints the figures and the fit's RAM.
#include <cstdint>

#include "firmware/core/device_fit.h"
#include "hw/boards/qemu-mps2/semihosting.h"
#include "tests/bench/m4/ticks.h"

namespace {

constexpr int kSide = 32;
constexpr int kPoints = kSide * kSide;
constexpr int kShortLine = 4;
dg::PointSample points[kPoints];
dg::DeviceFit device_fit;
dg::DeviceFit::Bezier bezier;
dg::DeviceFit::Net net;
dg::DeviceFit::Bezier::Workspace bezier_work;
dg::DeviceFit::Net::Workspace net_work;
digitizer_FitResult result;


template <typename F>
uint32_t measure(F&& work) {
  dg::bench::start_ticks();
  work();
  return dg::bench::ticks_since_start();
}

void report(const char* what, uint64_t instructions, uint32_t per) {
  dg::bench::write_text(what);
  dg::bench::write_number((instructions + per / 2) / per);
  dg::bench::write_text("\n");
}

}  // namespace

int main() {
  // A 200 x 200 mm region at the device's resolution; heights of a shallow dome (mm range).
  for (int j = 0; j < kSide; ++j) {
    for (int i = 0; i < kSide; ++i) {
      const int64_t dx = (i - 15) * 6451612, dy = (j - 15) * 6451612;  // nm
      dg::PointSample& p = points[j * kSide + i];
      p.x_nm = static_cast<int32_t>(i * 6451612);
      p.y_nm = static_cast<int32_t>(j * 6451612);
      p.z_nm = static_cast<int32_t>(8000000 - (dx * dx + dy * dy) / 2000000000);
    }
  }
  const uint64_t milli_per_tick = dg::bench::milli_instructions_per_tick();
  auto instructions = [&](uint32_t ticks) { return ticks * milli_per_tick / 1000; };

  digitizer_ScanRequest request = digitizer_ScanRequest_init_zero;
  request.scan_id = 1;
  request.x.max_nm = request.y.max_nm = 200000000;
  dg::fit::FitRegion region;
  region.x_max_nm = region.y_max_nm = 200000000;

  device_fit.begin(request);
  const uint32_t both = measure([] {
    for (const auto& p : points) device_fit.add(p);
  });
  bezier.begin(region);
  const uint32_t bezier_ticks = measure([] {
    for (const auto& p : points) bezier.add(p.x_nm, p.y_nm, p.z_nm);
  });
  net.begin(region);
  const uint32_t net_ticks = measure([] {
    for (const auto& p : points) net.add(p.x_nm, p.y_nm, p.z_nm);
  });
  // Short scan lines (256 lines of 4 points, the same region): the sums are per block, not per
  // line, so a point must cost the same here (per-line sums had cost three times as much).
  for (int j = 0; j < kPoints / kShortLine; ++j) {
    for (int i = 0; i < kShortLine; ++i) {
      // Each line's 4 points 50 mm apart, shifted 3.1 mm more on each of 16 lines, so the lines
      // together cover every span of the net.
      const int64_t x = int64_t{i} * 50000000 + (j % 16) * 3100000;
      const int64_t dx = x - 100000000, dy = (j - 127) * 784313;  // nm
      dg::PointSample& p = points[j * kShortLine + i];
      p.x_nm = static_cast<int32_t>(x);
      p.y_nm = static_cast<int32_t>(j * 784313);
      p.z_nm = static_cast<int32_t>(8000000 - (dx * dx + dy * dy) / 2000000000);
    }
  }
  device_fit.begin(request);
  const uint32_t both_short = measure([] {
    for (const auto& p : points) device_fit.add(p);
  });
  bezier.begin(region);
  const uint32_t bezier_short = measure([] {
    for (const auto& p : points) bezier.add(p.x_nm, p.y_nm, p.z_nm);
  });
  net.begin(region);
  const uint32_t net_short = measure([] {
    for (const auto& p : points) net.add(p.x_nm, p.y_nm, p.z_nm);
  });
  static int32_t bezier_heights[4][4];
  static int32_t net_heights[5][5];
  const uint32_t bezier_solve = measure([] { bezier.solve(bezier_heights, bezier_work); });
  const uint32_t net_solve = measure([] { net.solve(net_heights, net_work); });
  const uint32_t pull = measure([] { device_fit.result(digitizer_DeviceFitModel_DEVICE_FIT_NET, true, &result); });

  dg::bench::write_text(dg::bench::kCoreName);
  dg::bench::write_text(", 1024 points over 200 x 200 mm in 32 lines of 32:\n");
  report("  instructions per point, Bezier patch and 5x5 net together (DeviceFit::add, one set of sums): ",
         instructions(both), kPoints);
  report("  instructions per point, Bezier patch alone: ", instructions(bezier_ticks), kPoints);
  report("  instructions per point, 5x5 net alone: ", instructions(net_ticks), kPoints);
  dg::bench::write_text("  the same region in 256 short lines of 4 points:\n");
  report("    instructions per point, both together: ", instructions(both_short), kPoints);
  report("    instructions per point, Bezier patch alone: ", instructions(bezier_short), kPoints);
  report("    instructions per point, 5x5 net alone: ", instructions(net_short), kPoints);
  dg::bench::write_text("  (target: at most 1000 per point for each fit, on lines of any length)\n");
  report("  instructions to solve the Bezier patch (16 unknowns): ", instructions(bezier_solve), 1);
  report("  instructions to solve the 5x5 net (25 unknowns): ", instructions(net_solve), 1);
  report("  instructions for a pull of the net (solve and FitResult): ", instructions(pull), 1);
  report("  RAM of the device's fits (DeviceFit, both fits and the shared workspace), bytes: ", sizeof(dg::DeviceFit), 1);
  dg::bench::write_text(result.status == digitizer_FitStatus_FIT_OK ? "  fit status: ok\n" : "  fit status: FAILED\n");
  return result.status == digitizer_FitStatus_FIT_OK ? 0 : 1;
}
