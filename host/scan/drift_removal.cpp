// Drift removal: the reference readings, less the scan's first point, interpolated in time.
#include "host/scan/drift_removal.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace dg::host {

namespace {

// One reading of the reference point: the scan's first point (knot 0) or a reference reading.
struct Knot {
  double t_s = 0;
  double drift_mm = 0;
  size_t index = 0;  // in scan.points
};

constexpr double kLargestDriftMm = 1.0;

bool is_reference(const PointSample& p) { return (p.flags & digitizer_PointFlag_POINT_REFERENCE) != 0; }

// The drift's second derivative at interior knot k from its neighbours' slopes (mm/s^2); 0 at the ends.
double curvature_at(const std::vector<Knot>& knots, size_t k) {
  if (k == 0 || k + 1 >= knots.size()) return 0;
  const double left = knots[k].t_s - knots[k - 1].t_s, right = knots[k + 1].t_s - knots[k].t_s;
  if (!(left > 0) || !(right > 0)) return 0;
  const double slope_left = (knots[k].drift_mm - knots[k - 1].drift_mm) / left;
  const double slope_right = (knots[k + 1].drift_mm - knots[k].drift_mm) / right;
  return 2 * (slope_right - slope_left) / (left + right);
}

// A bound on the straight line's error between knots k and k + 1: M h^2 / 8 with M the larger
// curvature at either end, where the readings show one. At the first and the last step, whose outer
// end has no curvature of its own, it is extrapolated from the two nearest (a warm-up bends most at
// its start). With two knots only, the step itself (a drift that is monotonic over the step strays
// from its chord by less).
double interpolation_bound(const std::vector<Knot>& knots, size_t k) {
  const size_t n = knots.size();
  const double h = knots[k + 1].t_s - knots[k].t_s;
  if (n < 3) return std::fabs(knots[k + 1].drift_mm - knots[k].drift_mm);
  double curvature = std::max(std::fabs(curvature_at(knots, k)), std::fabs(curvature_at(knots, k + 1)));
  if (n >= 4 && k == 0) curvature = std::max(curvature, std::fabs(2 * curvature_at(knots, 1) - curvature_at(knots, 2)));
  if (n >= 4 && k + 2 == n) {
    curvature = std::max(curvature, std::fabs(2 * curvature_at(knots, n - 2) - curvature_at(knots, n - 3)));
  }
  return curvature * h * h / 8;
}

}  // namespace

std::optional<DriftRemoval> remove_drift(ScanData& scan, std::vector<double>* sigma_mm, const std::string& name,
                                         bool remove) {
  std::vector<PointSample>& points = scan.points;
  if (std::none_of(points.begin(), points.end(), is_reference)) return std::nullopt;
  const bool with_sigma = sigma_mm != nullptr && sigma_mm->size() == points.size();
  DriftRemoval out;
  if (remove) {
    const auto first = std::find_if(points.begin(), points.end(), [](const PointSample& p) {
      return !is_reference(p) && p.line == 0 && (p.flags & digitizer_PointFlag_POINT_LINE_START) != 0;
    });
    if (first == points.end()) {
      throw std::invalid_argument(name + ": the scan has reference readings but not its first point, which they repeat");
    }
    std::vector<Knot> knots{{0.0, 0.0, static_cast<size_t>(first - points.begin())}};
    for (size_t i = 0; i < points.size(); ++i) {
      if (!is_reference(points[i])) continue;
      if (std::llabs(static_cast<long long>(points[i].x_nm) - first->x_nm) > 1000 ||
          std::llabs(static_cast<long long>(points[i].y_nm) - first->y_nm) > 1000) {
        throw std::invalid_argument(name + ": reference reading " + std::to_string(points[i].seq) + " was taken at (" +
                                    std::to_string(points[i].x_nm * 1e-6) + ", " + std::to_string(points[i].y_nm * 1e-6) +
                                    ") mm, not at the scan's first point");
      }
      const double t_s = (static_cast<double>(points[i].t_us) - static_cast<double>(first->t_us)) * 1e-6;
      if (!(t_s > knots.back().t_s)) {
        throw std::invalid_argument(name + ": reference reading " + std::to_string(points[i].seq) +
                                    " is not later than the reading before it");
      }
      const double drift_mm = (static_cast<double>(points[i].z_nm) - first->z_nm) * 1e-6;
      // A stand drifts by micrometres, tens at most; a millimetre is a part or a gauge that moved.
      if (std::fabs(drift_mm) > kLargestDriftMm) {
        char text[200];
        std::snprintf(text, sizeof text,
                      ": reference reading %u differs from the scan's first point by %.3f mm: the part or the gauge "
                      "moved during the scan, which no drift correction mends",
                      static_cast<unsigned>(points[i].seq), drift_mm);
        throw std::invalid_argument(name + text);
      }
      knots.push_back({t_s, drift_mm, i});
      ++out.readings;
      out.largest_mm = std::max(out.largest_mm, std::fabs(knots.back().drift_mm));
    }
    std::vector<double> bound(knots.size() - 1);
    for (size_t k = 0; k + 1 < knots.size(); ++k) {
      bound[k] = interpolation_bound(knots, k);
      out.interpolation_mm = std::max(out.interpolation_mm, bound[k]);
    }
    const std::vector<double> sigma_before = with_sigma ? *sigma_mm : std::vector<double>{};
    for (size_t i = 0; i < points.size(); ++i) {
      if (is_reference(points[i])) continue;
      const double t_s = (static_cast<double>(points[i].t_us) - static_cast<double>(first->t_us)) * 1e-6;
      // The segment the point's time falls in; after the last reading the drift is held there, and
      // its error bounded by the last segment's rate over the time since.
      size_t k = 0;
      while (k + 2 < knots.size() && t_s > knots[k + 1].t_s) ++k;
      double w = std::clamp((t_s - knots[k].t_s) / (knots[k + 1].t_s - knots[k].t_s), 0.0, 1.0);
      double stray_mm = bound[k];
      if (t_s > knots.back().t_s) {
        const Knot& a = knots[knots.size() - 2];
        const Knot& b = knots.back();
        stray_mm = std::fabs((b.drift_mm - a.drift_mm) / (b.t_s - a.t_s)) * (t_s - b.t_s);
        w = 1;
      }
      const double drift = (1 - w) * knots[k].drift_mm + w * knots[k + 1].drift_mm;
      points[i].z_nm = static_cast<int32_t>(std::lround(points[i].z_nm - drift * 1e6));
      // drift = (1 - w) r_k + w r_(k+1) - r_0: the readings' weights, knot 0's reading counted once.
      double u2 = stray_mm * stray_mm / 3;
      if (with_sigma) {
        double weight[2] = {1 - w, w};
        double first_weight = -1;
        for (int e = 0; e < 2; ++e) {
          const size_t knot = k + static_cast<size_t>(e);
          if (knot == 0) {
            first_weight += weight[e];
          } else {
            const double s = sigma_before[knots[knot].index];
            u2 += weight[e] * weight[e] * s * s;
          }
        }
        const double s0 = sigma_before[knots[0].index];
        u2 += first_weight * first_weight * s0 * s0;
        (*sigma_mm)[i] = std::sqrt((*sigma_mm)[i] * (*sigma_mm)[i] + u2);
      }
      out.u_max_mm = std::max(out.u_max_mm, std::sqrt(u2));
    }
  }
  // The reference readings leave the points (and their uncertainties) in one pass.
  size_t kept = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (is_reference(points[i])) continue;
    points[kept] = points[i];
    if (with_sigma) (*sigma_mm)[kept] = (*sigma_mm)[i];
    ++kept;
  }
  points.resize(kept);
  if (with_sigma) sigma_mm->resize(kept);
  if (!remove) return std::nullopt;
  return out;
}

}  // namespace dg::host
