// Trying the usual gauge steps from the coarsest: the first that 99 % of the heights are whole
// multiples of is the reading's.
#include "host/scan/reading_step.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace dg::host {

namespace {

// Some two of the values are one step apart: `multiples` hold round(z / q) of the values that are
// whole multiples of q.
bool two_one_step_apart(std::vector<long long>& multiples) {
  if (multiples.size() < 2) return false;
  const auto [lo, hi] = std::minmax_element(multiples.begin(), multiples.end());
  const long long low = *lo;
  const unsigned long long range = static_cast<unsigned long long>(*hi - *lo);
  if (range <= 4 * multiples.size() + (1u << 20)) {
    std::vector<char> present(range + 1, 0);
    for (long long k : multiples) present[static_cast<size_t>(k - low)] = 1;
    for (size_t k = 1; k < present.size(); ++k) {
      if (present[k] && present[k - 1]) return true;
    }
    return false;
  }
  std::sort(multiples.begin(), multiples.end());
  for (size_t k = 1; k < multiples.size(); ++k) {
    if (multiples[k] - multiples[k - 1] == 1) return true;
  }
  return false;
}

}  // namespace

double detect_resolution_mm(const std::vector<Point3>& points) {
  if (points.size() < 8) return 0.0;
  static const double kSteps[] = {0.01, 0.005, 0.00254, 0.002, 0.00127, 0.001, 0.0005, 0.0001};
  // A step is the reading's when 99 % of the heights are whole multiples of it; one more than 1 %
  // that are not rules it out at once (a million unrounded heights took 8 full passes). And some
  // two heights must lie one step apart: a flat part read at 5.000 mm, nearly every reading alike,
  // is a whole multiple of every step, and took 10 um for the step of a 1 um gauge.
  const size_t allowed = points.size() - points.size() * 99 / 100;
  std::vector<long long> multiples;
  for (double q : kSteps) {
    size_t off = 0;
    multiples.clear();
    for (const Point3& p : points) {
      const double k = p.z / q;
      const double whole = std::round(k);
      if (std::fabs(k - whole) < 1e-3) {
        multiples.push_back(static_cast<long long>(whole));
      } else if (++off > allowed) {
        break;
      }
    }
    if (off <= allowed && two_one_step_apart(multiples)) return q;
  }
  return 0.0;
}

double rounding_sigma_mm(double step_mm) { return step_mm / std::sqrt(12.0); }

}  // namespace dg::host
