// Summary statistics of signed deviations (mm): the numbers a fit or an inspection reports.
#pragma once
#include <cstddef>
#include <vector>

namespace dg::host {

struct DistanceStats {
  size_t count = 0;
  double mean = 0, median = 0, stddev = 0, rms = 0, max = 0, min = 0, max_abs = 0;
};

DistanceStats distance_stats(const std::vector<double>& signed_distances);

}  // namespace dg::host
