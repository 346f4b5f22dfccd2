// Noise estimates from fifth differences along scan lines and columns, or local quadratics for scattered points.
#include "host/fit/noise_estimate.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include "host/fit/knot_support.h"
#include "host/scan/difference_noise.h"
#include "host/scan/local_polynomial.h"
#include "host/geometry/vec3.h"
#include "host/scan/median.h"
#include "host/scan/reading_step.h"

namespace dg::host {

namespace {

double from_lines(const PointCloud& cloud) {
  std::map<uint32_t, std::vector<size_t>> by_line;
  for (size_t i = 0; i < cloud.points.size(); ++i) by_line[(*cloud.line)[i]].push_back(i);
  std::vector<std::vector<size_t>> lines;
  // Columns too: on a grid, the points of equal x across the lines (in line order) are a second set
  // of evenly spaced sequences, which doubles the differences and halves their variance.
  std::map<long long, std::vector<size_t>> by_column;
  for (auto& [id, members] : by_line) {
    for (size_t i : members) by_column[std::llround(cloud.points[i].x * 1e4)].push_back(i);
    lines.push_back(std::move(members));
  }
  for (auto& [x, members] : by_column) {
    if (members.size() > static_cast<size_t>(kNoiseDifferenceOrder)) lines.push_back(std::move(members));
  }
  return difference_noise_sigma(cloud.points, lines);
}

double from_cells(const PointCloud& cloud, const Parameters& params) {
  // Cells of about 24 points, each fitted with a quadratic z(x, y) (6 coefficients) so that the
  // part's curvature does not pass for noise; the residual deviation uses n - 6 degrees of freedom.
  // At most about 100,000 points, evenly strided, take part: the median over thousands of cells is
  // as good as over more, and a million points would take a tenth of a second.
  const size_t stride = std::max<size_t>(1, cloud.points.size() / 100000);
  const double n = static_cast<double>(cloud.points.size() / stride);
  // As many cells across each direction, unless the points take too few distinct values along one
  // (a grid of few lines read without its line numbers): a quadratic needs three in each direction
  // and a cell is given four, and the cells are made longer along the other direction instead. With
  // square cells a 50 x 8 grid had two lines a cell, no quadratic was determined, and no noise was
  // estimated at all (characterize then took noise for curvature).
  int side_u = std::max(1, static_cast<int>(std::sqrt(n / 24.0))), side_v = side_u;
  std::vector<UV> sampled;
  for (size_t i = 0; i < cloud.points.size(); i += stride) sampled.push_back(params.uv[i]);
  const double merge = site_merge_distance(sampled.size());
  const int most_u = std::max<int>(1, static_cast<int>(distinct_sites(sampled, true, merge).size() / 4));
  const int most_v = std::max<int>(1, static_cast<int>(distinct_sites(sampled, false, merge).size() / 4));
  if (side_v > most_v) side_v = most_v, side_u = std::min(most_u, std::max(1, static_cast<int>(n / 24.0 / side_v)));
  if (side_u > most_u) side_u = most_u, side_v = std::min(most_v, std::max(1, static_cast<int>(n / 24.0 / side_u)));
  std::vector<std::vector<size_t>> cells(static_cast<size_t>(side_u) * side_v);
  for (size_t i = 0; i < cloud.points.size(); i += stride) {
    const int cu = std::min(side_u - 1, static_cast<int>(params.uv[i].u * side_u));
    const int cv = std::min(side_v - 1, static_cast<int>(params.uv[i].v * side_v));
    cells[static_cast<size_t>(cu) * side_v + cv].push_back(i);
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

NoiseEstimate estimate_gauge_noise(const PointCloud& cloud, const Parameters& params) {
  NoiseEstimate e;
  e.resolution_mm = cloud.resolution_mm ? *cloud.resolution_mm : detect_resolution_mm(cloud.points);
  double reading = 0;
  if (cloud.line) reading = from_lines(cloud);
  if (!(reading > 0)) reading = from_cells(cloud, params);
  if (!(reading > 0)) return e;
  const double step_sigma = rounding_sigma_mm(e.resolution_mm);
  const double rounding = step_sigma * step_sigma;
  // A reading rounded to q is uncertain by q / sqrt(12) however alike the readings are (the GUM's
  // rectangular distribution of a resolution): on a flat read with 0.3 um of noise on a 1 um gauge
  // nine in ten readings agree, their differences came out at 0.13 um, and the surface's stated
  // uncertainty with them.
  reading = std::max(reading, step_sigma);
  e.reading_sigma_mm = reading;
  // Sheppard's correction: rounding to q adds q^2 / 12 to the readings' variance. Below that the
  // noise cannot be told from the rounding; a quarter of the rounding variance is kept as a floor.
  e.sigma_mm = std::sqrt(std::max(reading * reading - rounding, 0.25 * rounding));
  return e;
}

double estimate_noise(const PointCloud& cloud, const Parameters& params) {
  return estimate_gauge_noise(cloud, params).sigma_mm;
}

}  // namespace dg::host
