// The tolerance contract on the simulated parts: kept or refused, and when kept, how far the surface
// is from the true part between the samples (a grid 4 times denser), RMS residual over the noise,
// the net and the time. One core, wall time with steady_clock.
#include <chrono>
#include <cstdio>

#include "host/fit/fit_error.h"
#include "host/fit/noise_estimate.h"
#include "host/fit/regions.h"
#include "host/fit/tolerance_fit.h"
#include "host/parallel/memory_reuse.h"
#include "tests/support/part_scan.h"

using namespace dg::host;

int main(int, char** argv) {
  tune_memory(argv, Restart::kAlways);  // huge pages, freed blocks kept (memory_reuse.h)
  std::printf("%-9s %5s %7s %-8s %9s %8s %7s %7s %s\n", "part", "noise", "tol", "result", "true-max", "rms/sig",
              "net", "time", "reason");
  int false_kept = 0;
  for (dg::sim::PartKind kind : {dg::sim::PartKind::kDome, dg::sim::PartKind::kSaddle, dg::sim::PartKind::kCanister}) {
    for (double sigma_um : {1.0, 2.0, 5.0}) {
      for (double factor : {2.0, 3.0, 5.0, 10.0, 25.0}) {
        dg::test::PartScan s;
        s.kind = kind;
        s.sigma_um = sigma_um;
        const PointCloud c = dg::test::scan_part(s, 3);
        const Parameters p = parameterize(c, Parameterization::kTableXy);
        ToleranceOptions o;
        o.tolerance_mm = factor * sigma_um * 1e-3;
        const auto t0 = std::chrono::steady_clock::now();
        ToleranceResult r;
        std::string error;
        try {
          r = fit_to_tolerance(c, p, nullptr, o);
        } catch (const FitError& e) {
          error = e.what();
        }
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (!error.empty()) {
          std::printf("%-9s %5.1f %7.4f %-8s %9s %8s %7s %6.2fs %s\n", dg::sim::part_name(kind), sigma_um, o.tolerance_mm,
                      "error", "-", "-", "-", seconds, error.c_str());
          continue;
        }
        const double truth = dg::test::max_error_against_part(r.surface, s);
        if (r.kept && truth > o.tolerance_mm) ++false_kept;
        char net[24];
        std::snprintf(net, sizeof net, "%dx%d", r.surface.count_u, r.surface.count_v);
        std::printf("%-9s %5.1f %7.4f %-8s %9.4f %8.2f %7s %6.2fs %.90s\n", dg::sim::part_name(kind), sigma_um,
                    o.tolerance_mm, r.kept ? "kept" : "refused", truth, r.rms_mm / (sigma_um * 1e-3), net, seconds,
                    r.kept ? "" : r.reason.c_str());
      }
    }
  }
  // The dome as trimmed faces: regions between its rim and base plate (fit's default for a creased scan).
  std::printf("\n%-9s %5s %7s %-8s %9s %8s %7s %7s %s\n", "regions", "noise", "tol", "result", "true-max", "faces",
              "points", "time", "reason");
  for (double sigma_um : {1.0, 2.0, 5.0}) {
    for (double factor : {2.0, 3.0, 5.0, 10.0, 25.0}) {
      dg::test::PartScan s;
      s.kind = dg::sim::PartKind::kDome;
      s.sigma_um = sigma_um;
      const PointCloud c = dg::test::scan_part(s, 3);
      RegionOptions o;
      o.tolerance.tolerance_mm = factor * sigma_um * 1e-3;
      const auto t0 = std::chrono::steady_clock::now();
      const RegionFit r = fit_regions(c, nullptr, o);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      int uncovered = 0;
      const double truth = r.faces.empty() ? 0.0 : dg::test::max_error_against_part(r.faces, s, 4, nullptr, &uncovered);
      if (r.kept && (truth > o.tolerance.tolerance_mm || uncovered > 0)) ++false_kept;
      std::printf("%-9s %5.1f %7.4f %-8s %9.4f %8zu %7zu %6.2fs %.90s\n", "dome", sigma_um, o.tolerance.tolerance_mm,
                  r.kept ? "kept" : "refused", truth, r.faces.size(), c.points.size(), seconds, r.kept ? "" : r.reason.c_str());
    }
  }
  std::printf("kept but farther than the tolerance from the true part somewhere: %d\n", false_kept);
  return false_kept == 0 ? 0 : 1;
}
