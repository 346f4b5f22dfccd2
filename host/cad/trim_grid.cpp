// Marking the cells of a face's parameter domain that lie inside its trims with a margin.
#include "host/cad/trim_grid.h"

#include <algorithm>
#include <cmath>

namespace dg::host {
namespace {

double distance_to_segment(double u, double v, const TrimGrid::Segment& s) {
  const double du = s[2] - s[0], dv = s[3] - s[1];
  const double length2 = du * du + dv * dv;
  double t = length2 > 0 ? ((u - s[0]) * du + (v - s[1]) * dv) / length2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(u - (s[0] + t * du), v - (s[1] + t * dv));
}

}  // namespace

TrimGrid::TrimGrid(const std::vector<Segment>& boundary, double sagitta, const std::function<bool(double, double)>& inside,
                   int cells_per_side) {
  if (boundary.empty() || cells_per_side < 1) return;
  if (!(sagitta >= 0) || !std::isfinite(sagitta)) return;
  double u1 = boundary[0][0], v1 = boundary[0][1];
  u0_ = u1;
  v0_ = v1;
  for (const Segment& s : boundary) {
    u0_ = std::min({u0_, s[0], s[2]});
    u1 = std::max({u1, s[0], s[2]});
    v0_ = std::min({v0_, s[1], s[3]});
    v1 = std::max({v1, s[1], s[3]});
  }
  if (!(u1 > u0_) || !(v1 > v0_) || !std::isfinite(u1 - u0_) || !std::isfinite(v1 - v0_)) return;
  n_ = cells_per_side;
  du_ = (u1 - u0_) / n_;
  dv_ = (v1 - v0_) / n_;
  const double margin = 0.5 * std::hypot(du_, dv_) + 2 * sagitta;
  inside_.assign(static_cast<size_t>(n_) * static_cast<size_t>(n_), 0);
  for (int j = 0; j < n_; ++j) {
    for (int i = 0; i < n_; ++i) {
      const double u = u0_ + (i + 0.5) * du_, v = v0_ + (j + 0.5) * dv_;
      bool clear = true;
      for (const Segment& s : boundary) {
        if (distance_to_segment(u, v, s) <= margin) {
          clear = false;
          break;
        }
      }
      inside_[static_cast<size_t>(j) * static_cast<size_t>(n_) + static_cast<size_t>(i)] = clear && inside(u, v);
    }
  }
}

bool TrimGrid::surely_inside(double u, double v) const {
  if (n_ == 0 || !(u >= u0_) || !(v >= v0_)) return false;
  const double fi = (u - u0_) / du_, fj = (v - v0_) / dv_;
  if (!(fi < n_) || !(fj < n_)) return false;
  return inside_[static_cast<size_t>(fj) * static_cast<size_t>(n_) + static_cast<size_t>(fi)] != 0;
}

}  // namespace dg::host
