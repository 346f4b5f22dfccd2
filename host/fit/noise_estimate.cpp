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

// The standard deviation of zero-mean normal values among outliers: the RMS of those within 3 s,
// divided by the RMS a normal distribution has within 3 sigma (0.98655), iterated from the MAD.
double truncated_sigma(const std::vector<double>& values) {
  std::vector<double> magnitude = values;
  for (double& v : magnitude) v = std::fabs(v);
  std::vector<double> copy = magnitude;
  double s = median_of(copy) / 0.6745;
  if (!(s > 0)) {
    // More than half the values are zero (readings coarser than the noise): start from the RMS of
    // the smaller 90 %.
    std::sort(copy.begin(), copy.end());
    double sum = 0;
    const size_t n = std::max<size_t>(1, copy.size() * 9 / 10);
    for (size_t i = 0; i < n; ++i) sum += copy[i] * copy[i];
    s = std::sqrt(sum / static_cast<double>(n));
    if (!(s > 0)) return 0.0;
  }
  for (int iteration = 0; iteration < 8; ++iteration) {
    double sum = 0;
    size_t n = 0;
    for (double v : magnitude) {
      if (v <= 3.0 * s) sum += v * v, ++n;
    }
    if (n == 0) break;
    const double next = std::sqrt(sum / static_cast<double>(n)) / 0.98655;
    if (std::fabs(next - s) <= 1e-6 * s) {
      s = next;
      break;
    }
    s = next;
  }
  return s;
}

// Differences of this order along a line cancel the part's shape up to a polynomial of one degree
// less; third differences left a bias of spacing^3 times the third derivative (18 % on the
// canister at 1 um of noise). Their noise has variance sum C(k, i)^2 sigma^2 = C(2k, k) sigma^2.
constexpr int kDifferenceOrder = 5;

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
    if (members.size() > static_cast<size_t>(kDifferenceOrder)) lines.push_back(std::move(members));
  }
  constexpr int k = kDifferenceOrder;
  double coefficient[k + 1];
  double variance_factor = 0;
  for (int i = 0; i <= k; ++i) {
    double binomial = 1;
    for (int m = 0; m < i; ++m) binomial = binomial * (k - m) / (m + 1);
    coefficient[i] = (i % 2 ? -1.0 : 1.0) * binomial;
    variance_factor += binomial * binomial;
  }
  // One sequence of differences per line or column, NaN where the spacing was uneven.
  std::vector<std::vector<double>> sequences;
  std::vector<double> all;
  for (const std::vector<size_t>& m : lines) {
    std::vector<double> sequence;
    for (size_t end = k; end < m.size(); ++end) {
      // Even spacing in the table plane, within 10 %, or the difference is not a noise measure.
      double lo = HUGE_VAL, hi = 0, value = 0;
      for (int i = 0; i <= k; ++i) {
        const Point3& p = cloud.points[m[end - k + static_cast<size_t>(i)]];
        value += coefficient[i] * p.z;
        if (i > 0) {
          const Point3& q = cloud.points[m[end - k + static_cast<size_t>(i) - 1]];
          const double step = std::hypot(p.x - q.x, p.y - q.y);
          lo = std::min(lo, step);
          hi = std::max(hi, step);
        }
      }
      const bool even = lo > 0 && hi <= 1.1 * lo;
      sequence.push_back(even ? value : std::nan(""));
      if (even) all.push_back(value);
    }
    sequences.push_back(std::move(sequence));
  }
  if (all.size() < 8) return 0.0;
  // A crease or a steep edge shows as a run of large differences; those past 3 sigma go, and so do
  // their neighbours within one window, whose shape part is still large but below the cut.
  const double first = truncated_sigma(all);
  std::vector<double> calm;
  for (const std::vector<double>& sequence : sequences) {
    for (size_t i = 0; i < sequence.size(); ++i) {
      if (std::isnan(sequence[i])) continue;
      bool near_edge = false;
      const size_t from = i >= static_cast<size_t>(k) ? i - k : 0, to = std::min(sequence.size() - 1, i + k);
      for (size_t j = from; j <= to && !near_edge; ++j) near_edge = std::fabs(sequence[j]) > 3.0 * first;
      if (!near_edge) calm.push_back(sequence[i]);
    }
  }
  const double sigma = calm.size() >= all.size() / 2 ? truncated_sigma(calm) : first;
  return sigma / std::sqrt(variance_factor);
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

double detect_resolution_mm(const std::vector<Point3>& points) {
  if (points.size() < 8) return 0.0;
  static const double kSteps[] = {0.01, 0.005, 0.00254, 0.002, 0.00127, 0.001, 0.0005, 0.0001};
  for (double q : kSteps) {
    size_t whole = 0;
    for (const Point3& p : points) {
      const double k = p.z / q;
      if (std::fabs(k - std::round(k)) < 1e-3) ++whole;
    }
    if (whole >= points.size() * 99 / 100) return q;
  }
  return 0.0;
}

NoiseEstimate estimate_gauge_noise(const PointCloud& cloud, const Parameters& params) {
  NoiseEstimate e;
  e.resolution_mm = cloud.resolution_mm ? *cloud.resolution_mm : detect_resolution_mm(cloud.points);
  double reading = 0;
  if (cloud.line) reading = from_lines(cloud);
  if (!(reading > 0)) reading = from_cells(cloud, params);
  if (!(reading > 0)) return e;
  e.reading_sigma_mm = reading;
  // Sheppard's correction: rounding to q adds q^2 / 12 to the readings' variance. Below that the
  // noise cannot be told from the rounding; a quarter of the rounding variance is kept as a floor.
  const double rounding = e.resolution_mm * e.resolution_mm / 12.0;
  e.sigma_mm = std::sqrt(std::max(reading * reading - rounding, 0.25 * rounding));
  return e;
}

double estimate_noise(const PointCloud& cloud, const Parameters& params) {
  return estimate_gauge_noise(cloud, params).sigma_mm;
}

}  // namespace dg::host
