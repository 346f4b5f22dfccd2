// Second-derivative bounds per knot cell from the differences of the control net.
#include "host/geometry/curvature_bound.h"

#include <algorithm>
#include <cmath>

#include "common/fit/bspline_basis.h"
#include "host/geometry/vec3.h"

namespace dg::host {

namespace {

double largest_coordinate(const Point3& p) { return std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}); }

// Scale of the first-difference control point k (Piegl and Tiller 1997, section 3.3): degree over
// the width of its basis function's support, 0 where that support is empty (its basis vanishes).
double first_scale(const std::vector<double>& knots, int degree, int k) {
  const double width = knots[static_cast<size_t>(k + degree + 1)] - knots[static_cast<size_t>(k + 1)];
  return width > 0 ? degree / width : 0.0;
}

// Scale of the second-difference control point k, the derivative of the first: (degree - 1) over
// its support's width, 0 where it is empty.
double second_scale(const std::vector<double>& knots, int degree, int k) {
  const double width = knots[static_cast<size_t>(k + degree + 1)] - knots[static_cast<size_t>(k + 2)];
  return width > 0 ? (degree - 1) / width : 0.0;
}

// Span s (degree <= s < count) starts at an interior knot repeated `degree` times or more: the
// surface has a kink (C0) or a step across it.
std::vector<char> kinks(const std::vector<double>& knots, int degree, int count) {
  std::vector<char> kink(static_cast<size_t>(count), 0);
  for (int s = degree + 1; s < count; ++s) {
    int multiplicity = 0;
    for (int k = s; k >= 0 && knots[static_cast<size_t>(k)] == knots[static_cast<size_t>(s)]; --k) ++multiplicity;
    kink[static_cast<size_t>(s)] = multiplicity >= degree;
  }
  return kink;
}

}  // namespace

CurvatureBound::CurvatureBound(const BSplineSurface& surface) : surface_(surface) {
  const BSplineSurface& s = surface;
  const int p = s.degree_u, q = s.degree_v;
  cells_u_ = s.count_u;
  cells_v_ = s.count_v;
  cell_bound_.assign(static_cast<size_t>(cells_u_) * cells_v_, 0.0);
  kink_before_u_ = kinks(s.knots_u, p, s.count_u);
  kink_before_v_ = kinks(s.knots_v, q, s.count_v);
  // First differences along u (D_u, count_u - 1 by count_v) and along v (D_v, count_u by count_v - 1).
  auto du = [&](int k, int l) { return first_scale(s.knots_u, p, k) * (s.at(k + 1, l) - s.at(k, l)); };
  auto dv = [&](int k, int l) { return first_scale(s.knots_v, q, l) * (s.at(k, l + 1) - s.at(k, l)); };
  for (int su = p; su < s.count_u; ++su) {
    if (!(s.knots_u[static_cast<size_t>(su)] < s.knots_u[static_cast<size_t>(su + 1)])) continue;  // empty span
    for (int sv = q; sv < s.count_v; ++sv) {
      if (!(s.knots_v[static_cast<size_t>(sv)] < s.knots_v[static_cast<size_t>(sv + 1)])) continue;
      double uu = 0, vv = 0, uv = 0;
      // S_uu: second differences along u, k in [su - p, su - 2], times the v basis, l in [sv - q, sv].
      for (int k = su - p; k <= su - 2; ++k) {
        const double scale = second_scale(s.knots_u, p, k);
        if (scale == 0) continue;
        for (int l = sv - q; l <= sv; ++l) uu = std::max(uu, largest_coordinate(scale * (du(k + 1, l) - du(k, l))));
      }
      for (int l = sv - q; l <= sv - 2; ++l) {
        const double scale = second_scale(s.knots_v, q, l);
        if (scale == 0) continue;
        for (int k = su - p; k <= su; ++k) vv = std::max(vv, largest_coordinate(scale * (dv(k, l + 1) - dv(k, l))));
      }
      // S_uv: first differences along both, k in [su - p, su - 1], l in [sv - q, sv - 1].
      for (int k = su - p; k <= su - 1; ++k) {
        for (int l = sv - q; l <= sv - 1; ++l) {
          uv = std::max(uv, largest_coordinate(first_scale(s.knots_v, q, l) * (du(k, l + 1) - du(k, l))));
        }
      }
      cell_bound_[static_cast<size_t>(su) * cells_v_ + sv] = std::max(uu, vv) + uv;
    }
  }
}

int CurvatureBound::span_u(double u) const {
  const std::vector<double>& k = surface_.knots_u;
  return fit::find_span(surface_.count_u, surface_.degree_u, std::clamp(u, k.front(), k.back()), k.data());
}

int CurvatureBound::span_v(double v) const {
  const std::vector<double>& k = surface_.knots_v;
  return fit::find_span(surface_.count_v, surface_.degree_v, std::clamp(v, k.front(), k.back()), k.data());
}

double CurvatureBound::along_any_direction(double u0, double u1, double v0, double v1) const {
  return over_spans(span_u(u0), span_u(u1), span_v(v0), span_v(v1));
}

double CurvatureBound::over_spans(int su0, int su1, int sv0, int sv1) const {
  if (su1 < su0) std::swap(su0, su1);
  if (sv1 < sv0) std::swap(sv0, sv1);
  for (int su = su0 + 1; su <= su1; ++su) {
    if (kink_before_u_[static_cast<size_t>(su)]) return HUGE_VAL;
  }
  for (int sv = sv0 + 1; sv <= sv1; ++sv) {
    if (kink_before_v_[static_cast<size_t>(sv)]) return HUGE_VAL;
  }
  double bound = 0;
  for (int su = su0; su <= su1; ++su) {
    for (int sv = sv0; sv <= sv1; ++sv) bound = std::max(bound, cell_bound_[static_cast<size_t>(su) * cells_v_ + sv]);
  }
  return bound;
}

}  // namespace dg::host
