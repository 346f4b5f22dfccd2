// Comparing a surface OpenCASCADE read back with ours: a 21 x 21 grid over the domain, relative 1e-9.
#pragma once
#include <CppUTest/TestHarness.h>

#include <Geom_BSplineSurface.hxx>
#include <cmath>

#include "host/geometry/bspline_surface.h"

namespace dg::test {

inline void check_evaluates_alike(const host::BSplineSurface& ours, const Handle(Geom_BSplineSurface)& theirs) {
  CHECK(!theirs.IsNull());
  double scale = 0;
  for (const host::Point3& p : ours.control) {
    scale = std::fmax(scale, std::fmax(std::fabs(p.x), std::fmax(std::fabs(p.y), std::fabs(p.z))));
  }
  for (int a = 0; a <= 20; ++a) {
    for (int b = 0; b <= 20; ++b) {
      const double u = ours.u_min() + (ours.u_max() - ours.u_min()) * a / 20.0;
      const double v = ours.v_min() + (ours.v_max() - ours.v_min()) * b / 20.0;
      const host::Point3 p = ours.evaluate(u, v);
      const gp_Pnt q = theirs->Value(u, v);
      DOUBLES_EQUAL(p.x, q.X(), 1e-9 * scale);
      DOUBLES_EQUAL(p.y, q.Y(), 1e-9 * scale);
      DOUBLES_EQUAL(p.z, q.Z(), 1e-9 * scale);
    }
  }
}

}  // namespace dg::test
