// Noise estimates from third differences along scan lines, or local quadratics for scattered points.
#include "host/fit/noise_estimate.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include "host/scan/local_polynomial.h"
#include "host/geometry/vec3.h"

namespace dg::host {

namespace {

double median_of(std::vector<double>& values) {
  if (values.empty()) return 0.0;
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  return values[mid];
}

double from_lines(const PointCloud& cloud) {
  std::map<uint32_t, std::vector<size_t>> lines;
  for (size_t i = 0; i < cloud.points.size(); ++i) lines[(*cloud.line)[i]].push_back(i);
  std::vector<double> d3;
  for (const auto& [id, m] : lines) {
    for (size_t k = 3; k < m.size(); ++k) {
      const Point3 &a = cloud.points[m[k - 3]], &b = cloud.points[m[k - 2]], &c = cloud.points[m[k - 1]],
                   &d = cloud.points[m[k]];
      // Even spacing in the table plane, within 10 %, or the difference is not a noise measure.
      const double s1 = std::hypot(b.x - a.x, b.y - a.y), s2 = std::hypot(c.x - b.x, c.y - b.y),
                   s3 = std::hypot(d.x - c.x, d.y - c.y);
      const double lo = std::min({s1, s2, s3}), hi = std::max({s1, s2, s3});
      if (!(lo > 0) || hi > 1.1 * lo) continue;
      d3.push_back(std::fabs(d.z - 3 * c.z + 3 * b.z - a.z));
    }
  }
  if (d3.size() < 8) return 0.0;
  return median_of(d3) / 0.6745 / std::sqrt(20.0);
}

double from_cells(const PointCloud& cloud, const Parameters& params) {
  // Cells of about 24 points, each fitted with a quadratic z(x, y) (6 coefficients) so that the
  // part's curvature does not pass for noise; the residual deviation uses n - 6 degrees of freedom.
  // At most about 100,000 points, evenly strided, take part: the median over thousands of cells is
  // as good as over more, and a million points would take a tenth of a second.
  const size_t stride = std::max<size_t>(1, cloud.points.size() / 100000);
  const double n = static_cast<double>(cloud.points.size() / stride);
  const int side = std::max(1, static_cast<int>(std::sqrt(n / 24.0)));
  std::vector<std::vector<size_t>> cells(static_cast<size_t>(side) * side);
  for (size_t i = 0; i < cloud.points.size(); i += stride) {
    const int cu = std::min(side - 1, static_cast<int>(params.uv[i].u * side));
    const int cv = std::min(side - 1, static_cast<int>(params.uv[i].v * side));
    cells[static_cast<size_t>(cu) * side + cv].push_back(i);
  }
  std::vector<double> sigmas;
  for (const auto& m : cells) {
    if (m.size() < 12) continue;
    Point3 centroid;
    for (size_t i : m) centroid.x += cloud.points[i].x, centroid.y += cloud.points[i].y;
    const double k = static_cast<double>(m.size());
    centroid.x /= k, centroid.y /= k;
    LocalPolynomial quadratic;
    if (!fit_local_polynomial(cloud.points, m, centroid, 2, quadratic)) continue;
    double ss = 0;
    for (size_t i : m) {
      const double r = cloud.points[i].z - quadratic.at(cloud.points[i].x, cloud.points[i].y);
      ss += r * r;
    }
    sigmas.push_back(std::sqrt(ss / (k - 6)));
  }
  if (sigmas.size() < 4) return 0.0;
  return median_of(sigmas);
}

}  // namespace

double estimate_noise(const PointCloud& cloud, const Parameters& params) {
  if (cloud.line) {
    const double sigma = from_lines(cloud);
    if (sigma > 0) return sigma;
  }
  return from_cells(cloud, params);
}

}  // namespace dg::host
