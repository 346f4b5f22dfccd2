// Curve evaluation through the shared basis, and a clamped surface's edges as curves.
#include "host/geometry/bspline_curve.h"

#include "common/fit/bspline_basis.h"
#include "host/geometry/vec3.h"

namespace dg::host {

Point3 BSplineCurve::evaluate(double t) const {
  double n[fit::kMaxDegree + 1];
  const int count = static_cast<int>(control.size());
  const int span = fit::find_span(count, degree, t, knots.data());
  fit::bspline_basis(span, degree, t, knots.data(), n);
  Point3 p;
  for (int a = 0; a <= degree; ++a) p += n[a] * control[static_cast<size_t>(span - degree + a)];
  return p;
}

std::vector<BSplineCurve> boundary_curves(const BSplineSurface& s) {
  auto row = [&](bool along_u, int fixed) {
    BSplineCurve c;
    c.degree = along_u ? s.degree_u : s.degree_v;
    c.knots = along_u ? s.knots_u : s.knots_v;
    const int n = along_u ? s.count_u : s.count_v;
    for (int k = 0; k < n; ++k) c.control.push_back(along_u ? s.at(k, fixed) : s.at(fixed, k));
    return c;
  };
  return {row(true, 0), row(false, s.count_u - 1), row(true, s.count_v - 1), row(false, 0)};
}

}  // namespace dg::host
