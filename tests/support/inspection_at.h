// Inspections for tests: points whose signed deviations are given, their x their index.
#pragma once
#include <vector>

#include "host/inspect/inspect.h"

namespace dg::test {

inline host::Inspection at_deviations(const std::vector<double>& deviations) {
  host::Inspection r;
  for (size_t i = 0; i < deviations.size(); ++i) {
    host::PointDeviation p{};
    p.point = host::Point3{static_cast<double>(i), 0, deviations[i]};
    p.foot = host::Point3{static_cast<double>(i), 0, 0};
    p.distance = deviations[i];
    r.points.push_back(p);
  }
  return r;
}

}  // namespace dg::test
