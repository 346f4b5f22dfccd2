// From a flat's grid scan to the travel's height-error map.
#include "host/scan/flat_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "host/scan/difference_noise.h"
#include "host/scan/local_polynomial.h"
#include "host/scan/reading_step.h"

namespace dg::host {

namespace {

constexpr size_t kMinNodes = 5;  // a quadratic through 5 x 5 neighbours needs that many each way
constexpr long kHalfWindow = 2;

// The distinct values of one coordinate and their common step; throws unless evenly spaced.
std::vector<double> axis_values(const std::vector<Point3>& points, bool y, const std::string& name) {
  std::vector<double> v;
  for (const Point3& p : points) v.push_back(y ? p.y : p.x);
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end(), [](double a, double b) { return std::fabs(a - b) < 1e-4; }), v.end());
  if (v.size() < kMinNodes) {
    throw CalibrationError(name + ": the flat's scan has " + std::to_string(v.size()) + " distinct " + (y ? "y" : "x") +
                           " positions; a map needs at least 5 each way");
  }
  const double step = (v.back() - v.front()) / static_cast<double>(v.size() - 1);
  for (size_t k = 0; k < v.size(); ++k) {
    if (std::fabs(v[k] - (v.front() + step * static_cast<double>(k))) > 1e-3) {
      throw CalibrationError(name + ": the flat's scan is not on an even grid (" + (y ? "y" : "x") + " = " +
                             std::to_string(v[k]) + " mm is off the step)");
    }
  }
  return v;
}

}  // namespace

TableCalibration calibrate_from_flat(const PointCloud& flat, double flatness_mm, const std::string& name) {
  if (!(flatness_mm >= 0) || !std::isfinite(flatness_mm)) throw CalibrationError("the flat's flatness must be a number >= 0");
  for (const Point3& p : flat.points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) throw CalibrationError(name + ": a point is not finite");
  }
  const std::vector<double> xs = axis_values(flat.points, false, name), ys = axis_values(flat.points, true, name);
  TableCalibration c;
  c.nx = xs.size(), c.ny = ys.size();
  c.x0_mm = xs.front(), c.y0_mm = ys.front();
  c.step_x_mm = (xs.back() - xs.front()) / static_cast<double>(c.nx - 1);
  c.step_y_mm = (ys.back() - ys.front()) / static_cast<double>(c.ny - 1);
  c.artefact_flatness_mm = flatness_mm;
  c.points = flat.points.size();
  // Each node's reading (the mean where a node was read more than once).
  std::vector<double> sum(c.nx * c.ny, 0.0);
  std::vector<int> count(c.nx * c.ny, 0);
  for (const Point3& p : flat.points) {
    const size_t i = static_cast<size_t>(std::lround((p.x - c.x0_mm) / c.step_x_mm));
    const size_t j = static_cast<size_t>(std::lround((p.y - c.y0_mm) / c.step_y_mm));
    sum[j * c.nx + i] += p.z;
    ++count[j * c.nx + i];
  }
  std::vector<Point3> nodes;
  for (size_t j = 0; j < c.ny; ++j) {
    for (size_t i = 0; i < c.nx; ++i) {
      if (count[j * c.nx + i] == 0) {
        char where[96];
        std::snprintf(where, sizeof where, "no reading at (%.3f, %.3f) mm", xs[i], ys[j]);
        throw CalibrationError(name + ": the flat's scan has a hole: " + where + "; the map needs every node");
      }
      nodes.push_back({xs[i], ys[j], sum[j * c.nx + i] / count[j * c.nx + i]});
    }
  }
  // The flat's plane: least squares over every node.
  std::vector<size_t> all(nodes.size());
  for (size_t k = 0; k < all.size(); ++k) all[k] = k;
  const Point3 middle{0.5 * (xs.front() + xs.back()), 0.5 * (ys.front() + ys.back()), 0};
  LocalPolynomial plane;
  if (!fit_local_polynomial(nodes, all, middle, 1, plane)) throw CalibrationError(name + ": the flat's plane is not determined");
  c.plane_mm[1] = plane.c[1] / plane.scale_x;
  c.plane_mm[2] = plane.c[2] / plane.scale_y;
  c.plane_mm[0] = plane.c[0] - c.plane_mm[1] * middle.x - c.plane_mm[2] * middle.y;
  std::vector<Point3> residual = nodes;
  for (Point3& p : residual) p.z -= plane.at(p.x, p.y);
  // The noise, from fifth differences along the rows and columns (not quantized by the gauge's step).
  std::vector<std::vector<size_t>> lines;
  for (size_t j = 0; j < c.ny; ++j) {
    lines.emplace_back();
    for (size_t i = 0; i < c.nx; ++i) lines.back().push_back(j * c.nx + i);
  }
  for (size_t i = 0; i < c.nx; ++i) {
    lines.emplace_back();
    for (size_t j = 0; j < c.ny; ++j) lines.back().push_back(j * c.nx + i);
  }
  c.noise_mm = difference_noise_sigma(residual, lines);
  if (c.noise_mm == 0 && flat.resolution_mm) c.noise_mm = rounding_sigma_mm(*flat.resolution_mm);
  const double u_flat = flatness_mm / 2 / std::sqrt(3.0);
  double ss = 0;
  std::vector<size_t> window;
  for (size_t j = 0; j < c.ny; ++j) {
    for (size_t i = 0; i < c.nx; ++i) {
      const long first_i = std::clamp<long>(static_cast<long>(i) - kHalfWindow, 0, static_cast<long>(c.nx) - 1 - 2 * kHalfWindow);
      const long first_j = std::clamp<long>(static_cast<long>(j) - kHalfWindow, 0, static_cast<long>(c.ny) - 1 - 2 * kHalfWindow);
      window.clear();
      for (long b = first_j; b <= first_j + 2 * kHalfWindow; ++b)
        for (long a = first_i; a <= first_i + 2 * kHalfWindow; ++a) window.push_back(static_cast<size_t>(b) * c.nx + static_cast<size_t>(a));
      LocalPolynomial q;
      const Point3& centre = residual[j * c.nx + i];
      if (!fit_local_polynomial(residual, window, centre, 2, q)) throw CalibrationError(name + ": a node's neighbourhood does not determine it");
      c.z_error_mm.push_back(q.c[0]);
      c.u_mm.push_back(std::hypot(c.noise_mm * std::sqrt(q.centre_gain), u_flat));
      ss += (centre.z - q.c[0]) * (centre.z - q.c[0]);
    }
  }
  c.residual_rms_mm = std::sqrt(ss / static_cast<double>(nodes.size()));
  return c;
}

}  // namespace dg::host
