// Deviation statistics: mean, median, sample standard deviation, RMS, extremes.
#include "host/geometry/distance_stats.h"

#include <algorithm>
#include <cmath>

namespace dg::host {

DistanceStats distance_stats(const std::vector<double>& d) {
  DistanceStats s;
  s.count = d.size();
  if (d.empty()) return s;
  double sum = 0, sum_sq = 0;
  s.max = s.min = d[0];
  for (double x : d) {
    sum += x;
    sum_sq += x * x;
    s.max = std::max(s.max, x);
    s.min = std::min(s.min, x);
  }
  const double n = static_cast<double>(d.size());
  s.mean = sum / n;
  s.rms = std::sqrt(sum_sq / n);
  double centred = 0;
  for (double x : d) centred += (x - s.mean) * (x - s.mean);
  s.stddev = d.size() > 1 ? std::sqrt(centred / (n - 1)) : 0.0;
  s.max_abs = std::max(std::fabs(s.max), std::fabs(s.min));
  std::vector<double> sorted = d;
  const size_t mid = sorted.size() / 2;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(mid), sorted.end());
  s.median = sorted[mid];
  if (sorted.size() % 2 == 0) s.median = 0.5 * (s.median + *std::max_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(mid)));
  return s;
}

}  // namespace dg::host
