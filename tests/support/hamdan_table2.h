// Hamdan 2010, Table 2: the boundary curve the paper's example fits, 51 points at x = 5 .. 20 mm in
// 0.3 mm steps, y constant, z rounded to 0.01 mm.
#pragma once
#include <vector>

#include "host/geometry/point3.h"

namespace dg::test {

inline std::vector<host::Point3> hamdan_table2() {
  static const double kZ[51] = {6.00,  6.24,  6.47,  6.70,  6.92,  7.14,  7.35,  7.55,  7.75,  7.94,  8.13,
                                8.31,  8.48,  8.64,  8.80,  8.95,  9.09,  9.23,  9.36,  9.47,  9.58,  9.69,
                                9.78,  9.86,  9.94,  10.00, 10.06, 10.10, 10.14, 10.16, 10.18, 10.18, 10.17,
                                10.16, 10.13, 10.09, 10.04, 9.97,  9.90,  9.81,  9.71,  9.60,  9.48,  9.34,
                                9.19,  9.02,  8.85,  8.66,  8.45,  8.23,  8.00};
  std::vector<host::Point3> points;
  for (int i = 0; i < 51; ++i) points.push_back({5.0 + 0.3 * i, 0.0, kZ[i]});
  return points;
}

}  // namespace dg::test
