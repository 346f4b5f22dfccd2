// Fuzzes what comes after parsing: a point set built from the bytes goes through one stage (the
// first byte picks it): the LTS filter, line splitting, characterization, the tolerance fit,
// profile curves, the superquadric, the noise estimate, inspection, tessellation and the mesh of
// trimmed faces cut at fuzzed loops. Every stage
// ends with a result or a clear error (FitError, std::invalid_argument, std::runtime_error); any
// other exception, a crash, a hang (libFuzzer's -timeout) or a blow-up (-rss_limit_mb) is a
// finding, and so is a non-finite number in a result.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <vector>

#include "host/fit/characterize.h"
#include "host/fit/fit_error.h"
#include "host/fit/noise_estimate.h"
#include "host/fit/profile_curve.h"
#include "host/fit/superquadric.h"
#include "host/fit/tolerance_fit.h"
#include "host/geometry/tessellate.h"
#include "host/inspect/inspect.h"
#include "host/scan/gauge_tilt_calibration.h"
#include "host/scan/lts_filter.h"
#include "host/scan/segment.h"
#include "host/scan/step_gauge_calibration.h"
#include "tests/support/sample_surfaces.h"

using namespace dg::host;

namespace {

class Bytes {
 public:
  Bytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  uint8_t byte() { return at_ < size_ ? data_[at_++] : 0; }
  int16_t word() { return static_cast<int16_t>(byte() | (byte() << 8)); }
  bool left() const { return at_ < size_; }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t at_ = 0;
};

void finite_or_trap(double v) {
  if (!std::isfinite(v)) __builtin_trap();
}

// A grid scan (heights from the bytes in micrometres around a tilted plane, read in 1 um steps) or
// scattered points (coordinates from the bytes in hundredths of a millimetre).
PointCloud cloud_from(Bytes& in) {
  PointCloud c;
  const uint8_t mode = in.byte();
  if (mode % 2 == 0) {
    const int nx = 2 + in.byte() % 30, ny = 2 + in.byte() % 30;
    c.line = std::vector<uint32_t>();
    c.resolution_mm = 0.001;
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const double z = 5.0 + 0.01 * i + in.word() * 1e-3;
        c.points.push_back({1.0 * i, 1.0 * j, std::round(z * 1000.0) / 1000.0});
        c.line->push_back(static_cast<uint32_t>(j));
      }
    }
  } else {
    while (in.left() && c.points.size() < 600) c.points.push_back({in.word() * 0.01, in.word() * 0.01, in.word() * 0.01});
  }
  return c;
}

ToleranceResult tolerance_fit(const PointCloud& cloud, double tolerance_mm, int iterations) {
  ToleranceOptions options;
  options.tolerance_mm = tolerance_mm;
  options.max_iterations = iterations;
  return fit_to_tolerance(cloud, parameterize(cloud, Parameterization::kTableXy), nullptr, options);
}

void run(uint8_t stage, const PointCloud& cloud) {
  switch (stage % 12) {
    case 0: {
      const LtsResult r = lts_filter(cloud.points, LtsOptions{});
      for (double z : r.z) finite_or_trap(z);
      finite_or_trap(r.sigma_mm);
      break;
    }
    case 1:
      segment_lines(cloud.points);
      break;
    case 2: {
      const Characterization c = characterize(cloud);
      for (const PointCharacter& p : c.points) finite_or_trap(p.mean_curvature + p.gaussian_curvature);
      break;
    }
    case 3: {
      const ToleranceResult r = tolerance_fit(cloud, 0.01, 6);
      finite_or_trap(r.max_distance_mm);
      finite_or_trap(r.rms_mm);
      for (const Point3& p : r.surface.control) finite_or_trap(p.x + p.y + p.z);
      break;
    }
    case 4: {
      std::vector<Point3> profile;
      for (const Point3& p : cloud.points) profile.push_back({p.x, 0.0, p.z});
      check_profile(profile, "fuzz");
      ApproximationReport report;
      const BSplineCurve c = approximate_clamped(profile, 4, &report);
      finite_or_trap(report.corrected_rms_mm);
      for (double d : curve_distances(c, profile)) finite_or_trap(d);
      curve_within_uncertainty(profile, 0.0003);
      break;
    }
    case 5: {
      SuperquadricOptions options;
      options.max_iterations = 20;
      const SuperquadricFit f = fit_superquadric(cloud.points, options);
      finite_or_trap(f.rms_radial_mm);
      break;
    }
    case 6: {
      const NoiseEstimate n = estimate_gauge_noise(cloud, parameterize(cloud, Parameterization::kTableXy));
      finite_or_trap(n.sigma_mm);
      break;
    }
    case 7: {
      const Inspection r = inspect(cloud.points, dg::test::tilted_plane(), {0.01});
      finite_or_trap(r.stats.rms);
      break;
    }
    case 8: {
      const ToleranceResult r = tolerance_fit(cloud, 0.05, 3);
      const Mesh m = tessellate(r.surface, 0.05, 50000);  // a budget a sanitized pass meets within the timeout
      for (const Point3& v : m.vertices) finite_or_trap(v.x + v.y + v.z);
      break;
    }
    case 9: {
      // The points' XY as a trim loop (any shape: crossing itself, on grid lines, off the plate)
      // over the 40 x 30 mm plate, and the plate with that loop as its hole.
      TrimmedFace inner, outer;
      inner.surface = outer.surface = dg::test::tilted_plane();
      TrimLoop loop;
      for (size_t i = 0; i < cloud.points.size() && loop.size() < 80; ++i) loop.push_back({cloud.points[i].x, cloud.points[i].y});
      if (loop.size() < 3) break;
      inner.loops = {loop};
      outer.loops = {{{0, 0}, {40, 0}, {40, 30}, {0, 30}}, TrimLoop(loop.rbegin(), loop.rend())};
      const Mesh m = tessellate_faces({inner, outer}, 0.05, 1.0, 200000);
      for (const Point3& v : m.vertices) finite_or_trap(v.x + v.y + v.z);
      for (const auto& t : m.triangles) {
        for (uint32_t k : t) {
          if (k >= m.vertices.size()) __builtin_trap();
        }
      }
      break;
    }
    case 10: {
      // The points as a reference sphere's readings (any shape: a plane, a cliff, a scatter).
      const GaugeTilt t = calibrate_gauge_tilt(cloud, 25.4, "fuzz");
      finite_or_trap(t.tilt_x_urad + t.tilt_y_urad + t.u_tilt_x_urad + t.u_tilt_y_urad + t.residual_rms_mm);
      break;
    }
    case 11: {
      // The points as a step gauge's readings against a six-step certificate.
      const GaugeScale g = calibrate_gauge_scale(cloud, {2, 4, 6, 8, 10, 12}, "fuzz");
      finite_or_trap(g.scale_ppm + g.u_scale_ppm + g.residual_rms_mm);
      break;
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Bytes in(data, size);
  const uint8_t stage = in.byte();
  const PointCloud cloud = cloud_from(in);
  try {
    run(stage, cloud);
  } catch (const FitError&) {
  } catch (const std::invalid_argument&) {
  } catch (const std::runtime_error&) {
  }
  return 0;
}
