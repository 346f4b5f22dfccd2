// The median of a set of values, for the robust scales of the filter and the noise estimates.
#pragma once
#include <algorithm>
#include <cstddef>
#include <vector>

namespace dg::host {

// The upper median (the middle element, or the upper of the two middle ones); 0 for no values.
// Reorders `values` (nth_element).
inline double median_in_place(std::vector<double>& values) {
  if (values.empty()) return 0.0;
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  return values[mid];
}

// The same of a copy.
inline double median_of(std::vector<double> values) { return median_in_place(values); }

}  // namespace dg::host
