// Point-in-polygon and parameter lookup for trimmed height-field faces.
#include "host/geometry/trimmed_face.h"

#include <algorithm>
#include <cmath>

namespace dg::host {

double twice_signed_area(const TrimLoop& loop) {
  double sum = 0;
  for (size_t i = 0, n = loop.size(); i < n; ++i) {
    const Point2& a = loop[i];
    const Point2& b = loop[(i + 1) % n];
    sum += a.x * b.y - b.x * a.y;
  }
  return sum;
}

bool inside_loop(const TrimLoop& loop, double x, double y) {
  bool inside = false;
  for (size_t i = 0, n = loop.size(), j = n - 1; i < n; j = i++) {
    const Point2& a = loop[i];
    const Point2& b = loop[j];
    if ((a.y > y) != (b.y > y) && x < (b.x - a.x) * (y - a.y) / (b.y - a.y) + a.x) inside = !inside;
  }
  return inside;
}

bool inside_face(const TrimmedFace& face, double x, double y) {
  if (face.loops.empty() || !inside_loop(face.loops[0], x, y)) return false;
  for (size_t k = 1; k < face.loops.size(); ++k) {
    if (inside_loop(face.loops[k], x, y)) return false;
  }
  return true;
}

void table_to_parameters(const BSplineSurface& s, double x, double y, double& u, double& v) {
  // A height field's x depends on u only and y on v only, linearly (bspline_fit.h): the corner
  // control points sit at their Greville abscissae, the domain's ends for clamped knots and beyond
  // them for the device's uniform net (-0.5 and 1.5).
  const Point3& first = s.at(0, 0);
  const Point3& last = s.at(s.count_u - 1, s.count_v - 1);
  const double tu = last.x != first.x ? (x - first.x) / (last.x - first.x) : 0.0;
  const double tv = last.y != first.y ? (y - first.y) / (last.y - first.y) : 0.0;
  const double gu0 = greville(s.knots_u, s.degree_u, 0), gu1 = greville(s.knots_u, s.degree_u, s.count_u - 1);
  const double gv0 = greville(s.knots_v, s.degree_v, 0), gv1 = greville(s.knots_v, s.degree_v, s.count_v - 1);
  u = gu0 + tu * (gu1 - gu0);
  v = gv0 + tv * (gv1 - gv0);
}

bool uncertainty_above(const BSplineSurface& surface, const SurfaceUncertainty& u, double x, double y, double& value) {
  double pu = 0, pv = 0;
  table_to_parameters(surface, x, y, pu, pv);
  return uncertainty_at(u, (pu - surface.u_min()) / (surface.u_max() - surface.u_min()),
                        (pv - surface.v_min()) / (surface.v_max() - surface.v_min()), value);
}

Point3 point_above(const BSplineSurface& surface, double x, double y) {
  double u, v;
  table_to_parameters(surface, x, y, u, v);
  return surface.evaluate(u, v);
}

TrimLoop densified(const TrimLoop& loop, double max_step_mm) {
  TrimLoop out;
  for (size_t i = 0, n = loop.size(); i < n; ++i) {
    const Point2& a = loop[i];
    const Point2& b = loop[(i + 1) % n];
    const double length = std::hypot(b.x - a.x, b.y - a.y);
    const int pieces = std::max(1, static_cast<int>(std::ceil(length / max_step_mm)));
    for (int k = 0; k < pieces; ++k) {
      const double t = static_cast<double>(k) / pieces;
      out.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
    }
  }
  return out;
}

}  // namespace dg::host
