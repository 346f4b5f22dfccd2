// Outliers planted on scans of the simulated parts' true shapes, for the LTS filter's recall and
// precision (a test and a benchmark).
#pragma once
#include <random>
#include <set>
#include <vector>

#include "tests/support/part_scan.h"

namespace dg::test {

struct Planted {
  std::vector<host::Point3> points;
  std::set<size_t> outliers;
};

// A 41 x 31 scan at 1 mm with `sigma_um` of noise and 1 um readings; 5 % of the points are moved by
// 20 to 250 sigma either way, and 12 pairs or triples of neighbours are moved together.
inline Planted plant_outliers(sim::PartKind kind, double sigma_um, unsigned seed) {
  PartScan s;
  s.kind = kind;
  s.sigma_um = sigma_um;
  Planted out;
  out.points = scan_part(s, seed).points;
  std::mt19937 rng(seed * 7 + 1);
  std::uniform_real_distribution<double> chance(0.0, 1.0), size(20.0, 250.0);
  auto move = [&](size_t i) {
    if (!out.outliers.insert(i).second) return;
    out.points[i].z += (chance(rng) < 0.5 ? -1 : 1) * size(rng) * sigma_um * 1e-3;
  };
  for (size_t i = 0; i < out.points.size(); ++i) {
    if (chance(rng) < 0.05) move(i);
  }
  std::uniform_int_distribution<size_t> any(0, out.points.size() - 1);
  for (int k = 0; k < 12; ++k) {
    const size_t i = any(rng);
    move(i);
    if (i + 1 < out.points.size()) move(i + 1);  // a neighbour along the line
    if (k % 2 && i + 41 < out.points.size()) move(i + 41);  // and one on the next line
  }
  return out;
}

}  // namespace dg::test
