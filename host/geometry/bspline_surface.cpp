// Evaluation of B-spline surfaces through the shared basis code of common/fit.
#include "host/geometry/bspline_surface.h"

#include <cmath>
#include <string>

#include "common/fit/bspline_basis.h"
#include "host/geometry/vec3.h"

namespace dg::host {

namespace {
constexpr int kMax = fit::kMaxDegree + 1;
}

Point3 BSplineSurface::evaluate(double u, double v) const {
  double nu[kMax], nv[kMax];
  const int su = fit::find_span(count_u, degree_u, u, knots_u.data());
  const int sv = fit::find_span(count_v, degree_v, v, knots_v.data());
  fit::bspline_basis(su, degree_u, u, knots_u.data(), nu);
  fit::bspline_basis(sv, degree_v, v, knots_v.data(), nv);
  Point3 s;
  for (int a = 0; a <= degree_u; ++a) {
    Point3 row;
    for (int b = 0; b <= degree_v; ++b) row += nv[b] * at(su - degree_u + a, sv - degree_v + b);
    s += nu[a] * row;
  }
  return s;
}

void BSplineSurface::evaluate(double u, double v, Point3& s, Point3& su_out, Point3& sv_out) const {
  double nu[kMax], nv[kMax], du[kMax], dv[kMax];
  const int su = fit::find_span(count_u, degree_u, u, knots_u.data());
  const int sv = fit::find_span(count_v, degree_v, v, knots_v.data());
  fit::bspline_basis(su, degree_u, u, knots_u.data(), nu, du);
  fit::bspline_basis(sv, degree_v, v, knots_v.data(), nv, dv);
  s = su_out = sv_out = Point3{};
  for (int a = 0; a <= degree_u; ++a) {
    Point3 row, row_dv;
    for (int b = 0; b <= degree_v; ++b) {
      const Point3& p = at(su - degree_u + a, sv - degree_v + b);
      row += nv[b] * p;
      row_dv += dv[b] * p;
    }
    s += nu[a] * row;
    su_out += du[a] * row;
    sv_out += nu[a] * row_dv;
  }
}

std::vector<double> clamped_uniform_knots(int count, int degree) {
  std::vector<double> knots(static_cast<size_t>(count + degree + 1));
  const int spans = count - degree;
  for (int i = 0; i < static_cast<int>(knots.size()); ++i) {
    if (i <= degree) knots[i] = 0.0;
    else if (i >= count) knots[i] = 1.0;
    else knots[i] = static_cast<double>(i - degree) / spans;
  }
  return knots;
}

double greville(const std::vector<double>& knots, int degree, int i) {
  if (degree == 0) return 0.5 * (knots[i] + knots[i + 1]);
  double sum = 0;
  for (int k = 1; k <= degree; ++k) sum += knots[i + k];
  return sum / degree;
}

std::vector<double> distinct_knots(const std::vector<double>& knots, double lo, double hi) {
  std::vector<double> distinct;
  for (double k : knots) {
    if (k >= lo && k <= hi && (distinct.empty() || k > distinct.back())) distinct.push_back(k);
  }
  return distinct;
}

bool is_valid(const BSplineSurface& s, std::string* why) {
  auto fail = [&](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  for (int d : {s.degree_u, s.degree_v}) {
    if (d < 1 || d > fit::kMaxDegree) return fail("degree must be 1.." + std::to_string(fit::kMaxDegree));
  }
  if (s.count_u <= s.degree_u || s.count_v <= s.degree_v) return fail("fewer control points than degree + 1");
  if (s.knots_u.size() != static_cast<size_t>(s.count_u + s.degree_u + 1) ||
      s.knots_v.size() != static_cast<size_t>(s.count_v + s.degree_v + 1)) {
    return fail("knot vector length is not control points + degree + 1");
  }
  if (s.control.size() != static_cast<size_t>(s.count_u) * s.count_v) return fail("control net size mismatch");
  for (const auto* k : {&s.knots_u, &s.knots_v}) {
    for (size_t i = 1; i < k->size(); ++i) {
      if (!((*k)[i] >= (*k)[i - 1])) return fail("knots decrease or are not numbers");
    }
  }
  if (!(s.u_max() > s.u_min()) || !(s.v_max() > s.v_min())) return fail("empty parameter domain");
  for (const auto& p : s.control) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return fail("control point is not finite");
  }
  return true;
}

}  // namespace dg::host
