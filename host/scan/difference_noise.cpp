// Binomial-weighted differences along sequences and a truncated RMS of them.
#include "host/scan/difference_noise.h"

#include <algorithm>
#include <cmath>

#include "host/scan/median.h"

namespace dg::host {

// The standard deviation of zero-mean normal values among outliers: the RMS of those within 3 s,
// divided by the RMS a normal distribution has within 3 sigma (0.98655), iterated from the lower
// quartile of |v|.
double truncated_sigma(const std::vector<double>& values) {
  std::vector<double> magnitude = values;
  for (double& v : magnitude) v = std::fabs(v);
  std::vector<double> copy = magnitude;
  // Started from the lower quartile of |v| (0.3186 sigma for normal values), not the median: steps
  // and outliers spoil more than half of a step gauge's differences at 1 mm, and a start from
  // their median settled on ten times the noise.
  const size_t quarter = copy.size() / 4;
  std::nth_element(copy.begin(), copy.begin() + static_cast<std::ptrdiff_t>(quarter), copy.end());
  double s = copy[quarter] / 0.3186;
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


double difference_noise_sigma(const std::vector<Point3>& points, const std::vector<std::vector<size_t>>& lines) {
  constexpr int k = kNoiseDifferenceOrder;
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
  // Each step between neighbours along a line, measured once: every difference spans k of them,
  // and measuring them again in each (five hypot calls a difference) took a grid of 1e5 points
  // 18 ms.
  std::vector<double> steps;
  for (const std::vector<size_t>& m : lines) {
    std::vector<double> sequence;
    steps.resize(m.size());
    for (size_t i = 1; i < m.size(); ++i) {
      const Point3& p = points[m[i]];
      const Point3& q = points[m[i - 1]];
      steps[i] = std::hypot(p.x - q.x, p.y - q.y);
    }
    for (size_t end = k; end < m.size(); ++end) {
      // Even spacing in the table plane, within 10 %, or the difference is not a noise measure.
      double lo = HUGE_VAL, hi = 0, value = 0;
      for (int i = 0; i <= k; ++i) {
        const size_t at = end - k + static_cast<size_t>(i);
        value += coefficient[i] * points[m[at]].z;
        if (i > 0) {
          lo = std::min(lo, steps[at]);
          hi = std::max(hi, steps[at]);
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
  // The calm ones are the estimate while a fifth of the windows remain: with 5 % outliers, each
  // spoiling the eleven windows within one of its own, fewer than half were left, and falling back
  // on all of them put the outliers' small shares back in (15 % high on the dome at 5 um).
  const double sigma = calm.size() >= all.size() / 5 ? truncated_sigma(calm) : first;
  return sigma / std::sqrt(variance_factor);
}

}  // namespace dg::host
