// Rigid alignment: points of a nominal surface moved by a known rotation and translation come back
// onto it, and the transform found undoes the one applied.
#include "host/fit/rigid_align.h"

#include <CppUTest/TestHarness.h>

#include <cmath>

#include "host/geometry/triangle_mesh.h"
#include "host/geometry/vec3.h"
#include "tests/support/sample_surfaces.h"

using namespace dg::host;

namespace {

// Points of the nominal at (a/30, b/30), turned 1.5 degrees about a tilted axis and shifted 0.4 mm.
std::vector<Point3> misplaced(const BSplineSurface& nominal) {
  const double angle = 1.5 * M_PI / 180;
  const Point3 axis{0.3, -0.2, 0.93};
  const Point3 u = (1.0 / norm(axis)) * axis;
  auto turn = [&](const Point3& p) {
    return std::cos(angle) * p + std::sin(angle) * cross(u, p) + (1 - std::cos(angle)) * dot(u, p) * u +
           Point3{0.4, -0.25, 0.3};
  };
  std::vector<Point3> measured;
  for (int a = 1; a < 30; ++a)
    for (int b = 1; b < 30; ++b) measured.push_back(turn(nominal.evaluate(a / 30.0, b / 30.0)));
  return measured;
}

}  // namespace

TEST_GROUP(RigidAlign){};

TEST(RigidAlign, UndoesAKnownMisplacement) {
  const BSplineSurface nominal = dg::test::clamped_sample();
  const SurfaceLocator locator(nominal);
  const std::vector<Point3> measured = misplaced(nominal);
  const Alignment r = align_to_surface(measured, locator);
  CHECK(r.converged);
  CHECK(r.rms_before_mm > 0.1);
  CHECK(r.rms_after_mm < 1e-5);
  DOUBLES_EQUAL(1.5, r.transform.angle_deg(), 0.01);
}

TEST(RigidAlign, LeavesAlignedPointsWhereTheyAre) {
  const BSplineSurface nominal = dg::test::clamped_sample();
  const SurfaceLocator locator(nominal);
  std::vector<Point3> measured;
  for (int a = 0; a <= 20; ++a)
    for (int b = 0; b <= 20; ++b) measured.push_back(nominal.evaluate(a / 20.0, b / 20.0));
  const Alignment r = align_to_surface(measured, locator);
  CHECK(r.rms_after_mm < 1e-6);  // the closest-point iteration settles to 1e-7 mm
  CHECK(r.transform.angle_deg() < 1e-6);
  CHECK(norm(r.transform.translation) < 1e-6);
}

TEST(RigidAlign, UndoesTheSameMisplacementAgainstTheSurfacesMesh) {
  // The nominal as a mesh (0.2 um chord), its normals the pseudo-normals of the nearest features:
  // the transform comes out as against the surface itself, within what the chord allows.
  const BSplineSurface nominal = dg::test::clamped_sample();
  const MeshLocator mesh(tessellate(nominal, 0.0002));
  const std::vector<Point3> measured = misplaced(nominal);
  const Alignment r = align_to_nominal(measured, [&](const Point3& p) { return mesh.closest(p); });
  CHECK(r.converged);
  CHECK(r.rms_before_mm > 0.1);
  CHECK(r.rms_after_mm < 0.0002);
  DOUBLES_EQUAL(1.5, r.transform.angle_deg(), 0.01);
}

TEST(RigidAlign, OutliersDoNotPullTheFit) {
  // The same misplacement with 5 % of the points lifted 1 mm (dirt, a burr, a feature the nominal
  // lacks): a plain least-squares step would tilt towards them; the trimmed one leaves them out.
  const BSplineSurface nominal = dg::test::clamped_sample();
  const SurfaceLocator locator(nominal);
  std::vector<Point3> measured = misplaced(nominal);
  size_t lifted = 0;
  for (size_t k = 0; k < measured.size(); k += 20, ++lifted) measured[k].z += 1.0;
  const Alignment r = align_to_surface(measured, locator);
  CHECK(r.converged);
  DOUBLES_EQUAL(1.5, r.transform.angle_deg(), 0.01);
  LONGS_EQUAL(lifted, r.left_out);
  // Every other point is back on the nominal.
  double worst = 0;
  for (size_t k = 0; k < measured.size(); ++k) {
    if (k % 20) worst = std::max(worst, std::fabs(locator.closest(r.transform.apply(measured[k])).distance));
  }
  CHECK(worst < 1e-5);
}
