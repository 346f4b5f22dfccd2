// Scans of the simulated parts' true shapes for fitting tests and benchmarks: a serpentine grid at
// 1 mm, Gaussian gauge noise, readings rounded to the gauge's step, with the true shape at hand as
// the oracle between the samples.
#pragma once
#include <algorithm>
#include <cmath>
#include <random>

#include "host/geometry/bspline_surface.h"
#include "host/geometry/trimmed_face.h"
#include "host/scan/point_reader.h"
#include "hw/sim/parts.h"

namespace dg::test {

struct PartScan {
  dg::sim::PartKind kind = dg::sim::PartKind::kDome;
  double sigma_um = 5;
  double step_um = 1;  // the reading step; 0 for unrounded readings
  int nx = 41, ny = 31;  // points per line, lines; 1 mm apart from (0, 0)
  double outlier_rate = 0, outlier_mm = 0.5;
};

// The canister's true shape on an nx x ny grid at 1 mm, without noise or rounding: for Monte Carlo
// checks, whose replicas add their own noise.
inline PartScan noiseless_canister(int nx = 41, int ny = 31) {
  PartScan s;
  s.kind = sim::PartKind::kCanister;
  s.sigma_um = 0;
  s.step_um = 0;
  s.nx = nx;
  s.ny = ny;
  return s;
}

inline host::PointCloud scan_part(const PartScan& s, unsigned seed, std::vector<size_t>* outliers = nullptr) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, s.sigma_um * 1e-3);
  std::uniform_real_distribution<double> chance(0.0, 1.0);
  host::PointCloud c;
  c.line = std::vector<uint32_t>();
  if (s.step_um > 0) c.resolution_mm = s.step_um * 1e-3;
  for (int j = 0; j < s.ny; ++j) {
    for (int k = 0; k < s.nx; ++k) {
      const int i = (j % 2) ? s.nx - 1 - k : k;
      double z = dg::sim::shape_height_mm(s.kind, i, j) + noise(rng);
      if (s.outlier_rate > 0 && chance(rng) < s.outlier_rate) {
        z += chance(rng) < 0.5 ? -s.outlier_mm : s.outlier_mm;
        if (outliers) outliers->push_back(c.points.size());
      }
      if (s.step_um > 0) z = std::round(z / (s.step_um * 1e-3)) * s.step_um * 1e-3;
      c.points.push_back({1.0 * i, 1.0 * j, z});
      c.line->push_back(static_cast<uint32_t>(j));
    }
  }
  return c;
}

// The largest |S - true part| over a grid `per_mm` times denser than the samples, inside the scanned
// rectangle; for a height field S(u, v) lies above table (x, y) = (u (nx - 1), v (ny - 1)).
inline double max_error_against_part(const host::BSplineSurface& surface, const PartScan& s, int per_mm = 4,
                                     host::Point3* where = nullptr) {
  double worst = 0;
  const int gx = (s.nx - 1) * per_mm, gy = (s.ny - 1) * per_mm;
  for (int a = 0; a <= gx; ++a) {
    for (int b = 0; b <= gy; ++b) {
      const double u = static_cast<double>(a) / gx, v = static_cast<double>(b) / gy;
      const host::Point3 p = surface.evaluate(u, v);
      const double e = std::fabs(p.z - dg::sim::shape_height_mm(s.kind, p.x, p.y));
      if (e > worst) {
        worst = e;
        if (where) *where = p;
      }
    }
  }
  return worst;
}

// The same for trimmed faces: each grid point is judged on the face whose loops hold it. A grid
// point on no face (on a shared boundary, where the even-odd test may miss both) takes the nearer of
// the faces whose surface spans it; `uncovered` counts those held by none at all.
inline double max_error_against_part(const std::vector<host::TrimmedFace>& faces, const PartScan& s, int per_mm = 4,
                                     host::Point3* where = nullptr, int* uncovered = nullptr) {
  double worst = 0;
  if (uncovered) *uncovered = 0;
  const int gx = (s.nx - 1) * per_mm, gy = (s.ny - 1) * per_mm;
  for (int a = 0; a <= gx; ++a) {
    for (int b = 0; b <= gy; ++b) {
      const double x = static_cast<double>(a) / per_mm, y = static_cast<double>(b) / per_mm;
      const double truth = dg::sim::shape_height_mm(s.kind, x, y);
      double e = HUGE_VAL;
      for (const host::TrimmedFace& f : faces) {
        if (!host::inside_face(f, x, y)) continue;
        double u, v;
        host::table_to_parameters(f.surface, x, y, u, v);
        e = std::fabs(f.surface.evaluate(u, v).z - truth);
        break;
      }
      if (e == HUGE_VAL) {
        for (const host::TrimmedFace& f : faces) {
          double u, v;
          host::table_to_parameters(f.surface, x, y, u, v);
          if (u < f.surface.u_min() || u > f.surface.u_max() || v < f.surface.v_min() || v > f.surface.v_max()) continue;
          e = std::min(e, std::fabs(f.surface.evaluate(u, v).z - truth));
        }
      }
      if (e == HUGE_VAL) {
        if (uncovered) ++*uncovered;
        continue;
      }
      if (e > worst) {
        worst = e;
        if (where) *where = {x, y, truth};
      }
    }
  }
  return worst;
}

}  // namespace dg::test
