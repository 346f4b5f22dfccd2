// Rigid alignment: points of a nominal surface moved by a known rotation and translation come back
// onto it, and the transform found undoes the one applied.
#include "host/fit/rigid_align.h"

#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "host/geometry/triangle_mesh.h"
#include "host/geometry/vec3.h"
#include "hw/sim/parts.h"
#include "tests/support/part_mesh.h"
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

// The part's true shape read every 1 mm over [x0, x1] x [y0, y1], turned 0.5 degrees about a tilted
// axis and shifted by a few tenths of a millimetre.
std::vector<Point3> misplaced_part(dg::sim::PartKind kind, int x0, int x1, int y0, int y1) {
  const double angle = 0.5 * M_PI / 180;
  const Point3 u = (1.0 / std::sqrt(0.3 * 0.3 + 0.2 * 0.2 + 0.93 * 0.93)) * Point3{0.3, -0.2, 0.93};
  std::vector<Point3> measured;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const Point3 p{static_cast<double>(x), static_cast<double>(y), dg::sim::shape_height_mm(kind, x, y)};
      measured.push_back(std::cos(angle) * p + std::sin(angle) * cross(u, p) + (1 - std::cos(angle)) * dot(u, p) * u +
                         Point3{0.3, -0.2, 0.05});
    }
  return measured;
}

}  // namespace

TEST_GROUP(RigidAlign){};

TEST(RigidAlign, APartLargerThanItsNominalIsAlignedByItsPointsOverIt) {
  // The canister read over 40 x 30 mm against its dish meshed over 24 x 18 mm: the points beyond the
  // mesh's border measure their distance to it, not along a normal, and would pull the part towards
  // it (a 12 mm "deviation"); left out, the misplacement is undone as if the scan fitted the mesh.
  const MeshLocator nominal(dg::test::part_mesh(dg::sim::PartKind::kCanister, 8, 32, 6, 24));
  const std::vector<Point3> measured = misplaced_part(dg::sim::PartKind::kCanister, 0, 40, 0, 30);
  const Alignment r = align_to_nominal(measured, [&](const Point3& p) { return nominal.closest(p); });
  CHECK(r.converged);
  CHECK(r.beyond_edge > 500);
  LONGS_EQUAL(0, r.held);
  CHECK(r.rms_after_mm < 0.001);
  DOUBLES_EQUAL(0.5, r.transform.angle_deg(), 0.01);
  // Each point over the mesh comes back within 0.01 mm of where the part's shape has it.
  for (const Point3& p : measured) {
    const Point3 back = r.transform.apply(p);
    if (back.x < 9 || back.x > 31 || back.y < 7 || back.y > 23) continue;
    DOUBLES_EQUAL(dg::sim::shape_height_mm(dg::sim::PartKind::kCanister, back.x, back.y), back.z, 0.001);
  }
}

TEST(RigidAlign, HoldsStillTheFreedomsTheNominalsShapeDoesNotFix) {
  // A patch of the dome's sphere turns about the sphere's centre without changing a distance: those
  // three freedoms are held, not moved at random, and the points still come back onto the sphere.
  const MeshLocator cap(dg::test::part_mesh(dg::sim::PartKind::kDome, 12, 28, 8, 22));
  const Alignment r = align_to_nominal(misplaced_part(dg::sim::PartKind::kDome, 13, 27, 9, 21),
                                       [&](const Point3& p) { return cap.closest(p); });
  CHECK(r.converged);
  LONGS_EQUAL(3, r.held);
  CHECK(r.rms_after_mm < 0.001);
  CHECK(r.transform.angle_deg() < 1.0);
  // A plane fixes only its height and its two tilts.
  const MeshLocator flat(dg::test::part_mesh(dg::sim::PartKind::kFlat, 0, 20, 0, 20));
  const Alignment f = align_to_nominal(misplaced_part(dg::sim::PartKind::kFlat, 2, 18, 2, 18),
                                       [&](const Point3& p) { return flat.closest(p); });
  LONGS_EQUAL(3, f.held);
  CHECK(f.rms_after_mm < 1e-6);
}

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

namespace {

// A 40 x 30 mm plate with two ridges 2 mm high: one along y at x = 30 (its flanks slope in x), one
// along x at y = 20 (flanks slope in y). Planar in every 0.5 mm cell, so the mesh is exact.
double ridges(double x, double y) {
  return std::max(0.0, 2 - 0.4 * std::fabs(x - 30)) + std::max(0.0, 2 - 0.4 * std::fabs(y - 20));
}

Mesh ridge_plate() { return dg::test::height_mesh(ridges, 0, 40, 0, 30, 0.5); }

// The part as measured: the plate's points (away from its border, so every point has its nominal
// under it) turned 0.8 degrees about a tilted axis and shifted.
std::vector<Point3> misplaced_plate() {
  const double angle = 0.8 * M_PI / 180;
  const Point3 u = (1.0 / norm(Point3{0.2, 0.3, 0.93})) * Point3{0.2, 0.3, 0.93};
  std::vector<Point3> measured;
  for (double y = 2; y <= 28; y += 0.5)
    for (double x = 2; x <= 38; x += 0.5) {
      const Point3 p{x, y, ridges(x, y)};
      measured.push_back(std::cos(angle) * p + std::sin(angle) * cross(u, p) + (1 - std::cos(angle)) * dot(u, p) * u +
                         Point3{0.3, -0.2, 0.15});
    }
  return measured;
}

DatumFit datum_in(const char* name, const std::vector<Point3>& points, double x0, double x1, double y0, double y1) {
  DatumFit d;
  d.name = name;
  for (const Point3& p : points)
    if (p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1) d.points.push_back(p);
  return d;
}

}  // namespace

// 3-2-1: A (flat plate) fixes tilt and height, B (the ridge's x flanks) the rotation about z and x,
// C (the other ridge's y flanks) y. Together they undo the misplacement: every point of the part,
// not only the datums', lands on the nominal.
TEST(RigidAlign, ThreeDatumsUndoAKnownMisplacement) {
  const MeshLocator nominal(ridge_plate());
  auto closest = [&](const Point3& p) { return nominal.closest(p); };
  const std::vector<Point3> measured = misplaced_plate();
  std::vector<DatumFit> datums = {datum_in("A", measured, 2, 18, 2, 12), datum_in("B", measured, 25, 35, 2, 12),
                                  datum_in("C", measured, 2, 14, 15, 25)};
  const Alignment r = align_to_datums(datums, closest);
  CHECK(r.rms_before_mm > 0.05);
  DOUBLES_EQUAL(0.8, r.transform.angle_deg(), 0.01);
  double worst = 0;
  for (const Point3& p : measured) worst = std::max(worst, std::fabs(nominal.closest(r.transform.apply(p)).distance));
  CHECK(worst < 1e-4);
  STRCMP_EQUAL("tilt about x and y, height", datums[0].fixes_text.c_str());
  STRCMP_EQUAL("rotation about z, x", datums[1].fixes_text.c_str());
  STRCMP_EQUAL("y", datums[2].fixes_text.c_str());
  CHECK(datums[1].rms_after_mm < 1e-4);
}

// Only the plate as datum A: tilt and height are undone, the part's x, y and turn about z are left
// as they were placed, so the ridges stay off (an honest, partial alignment).
TEST(RigidAlign, OneDatumFixesOnlyTiltAndHeight) {
  const MeshLocator nominal(ridge_plate());
  const std::vector<Point3> measured = misplaced_plate();
  std::vector<DatumFit> datums = {datum_in("A", measured, 2, 18, 2, 12)};
  const Alignment r = align_to_datums(datums, [&](const Point3& p) { return nominal.closest(p); });
  CHECK(datums[0].rms_after_mm < 1e-4);
  // The plate's own points are flat now: z = 0 after the transform.
  for (const Point3& p : datums[0].points) DOUBLES_EQUAL(0.0, r.transform.apply(p).z, 1e-4);
}

// A second datum on the flat plate cannot fix x, y or the turn: refused, naming it.
TEST(RigidAlign, ADatumThatCannotFixItsFreedomsIsRefusedByName) {
  const MeshLocator nominal(ridge_plate());
  const std::vector<Point3> measured = misplaced_plate();
  std::vector<DatumFit> datums = {datum_in("A", measured, 2, 18, 2, 12), datum_in("B", measured, 2, 12, 2, 10)};
  try {
    align_to_datums(datums, [&](const Point3& p) { return nominal.closest(p); });
    FAIL("a flat secondary datum was accepted");
  } catch (const std::invalid_argument& e) {
    STRCMP_CONTAINS("datum B cannot fix", e.what());
  }
  // B on the ridge that slopes only in x: with two datums it must fix y too, and cannot.
  std::vector<DatumFit> x_only = {datum_in("A", measured, 2, 18, 2, 12), datum_in("B", measured, 25, 35, 2, 12)};
  try {
    align_to_datums(x_only, [&](const Point3& p) { return nominal.closest(p); });
    FAIL("a secondary datum that slopes only in x was asked to fix y and accepted");
  } catch (const std::invalid_argument& e) {
    STRCMP_CONTAINS("datum B cannot fix the y", e.what());
  }
  std::vector<DatumFit> none = {datum_in("A", measured, 100, 110, 2, 12)};
  CHECK_THROWS(std::invalid_argument, align_to_datums(none, [&](const Point3& p) { return nominal.closest(p); }));
}

// A datum A in a strip along the nominal's edge, on a part read 0.5 mm off in x: A fits over the
// nominal, then B moves the part 0.5 mm and carries every point of A beyond the edge. A has no RMS
// left to give (it came out 0 from no points): refused, naming it.
TEST(RigidAlign, ADatumCarriedBeyondTheNominalsEdgeIsRefusedByName) {
  const MeshLocator nominal(ridge_plate());
  DatumFit a;
  a.name = "A";
  for (double y = 2; y <= 28; y += 0.5)
    for (double x = 40.05; x <= 40.36; x += 0.1) a.points.push_back({x - 0.5, y, ridges(x, y)});
  DatumFit b;
  b.name = "B";
  for (double y = 15; y <= 25; y += 0.5)
    for (double x = 25; x <= 35; x += 0.5) b.points.push_back({x - 0.5, y, ridges(x, y)});
  std::vector<DatumFit> datums = {a, b};
  try {
    align_to_datums(datums, [&](const Point3& p) { return nominal.closest(p); });
    FAIL("a datum with no point over the nominal was given an RMS");
  } catch (const std::invalid_argument& e) {
    STRCMP_CONTAINS("datum A: every one of its points lies beyond the nominal's edge", e.what());
  }
}

// The simulated dome already in place, read on a 1 mm grid with 2 um of noise in whole micrometres,
// against its own shape meshed at 0.2 mm: the trimmed best fit hops between subsets of points at
// the rim without settling, and once wandered 10 um off, raising the RMS by a fifth. It must never
// leave a well-placed part worse than it found it (it keeps the best transform it saw).
TEST(RigidAlign, NeverLeavesAWellPlacedPartWorse) {
  const MeshLocator nominal(dg::test::part_mesh(dg::sim::PartKind::kDome, 0, 40, 0, 30));
  std::vector<Point3> measured;
  uint32_t state = 12345;
  auto noise_mm = [&state] {
    double sum = 0;  // about Gaussian: a sum of 12 uniforms has sigma 1; times 2 um
    for (int k = 0; k < 12; ++k) sum += (state = state * 1664525u + 1013904223u) / 4294967296.0;
    return 0.002 * (sum - 6);
  };
  for (int y = 0; y <= 30; ++y)
    for (int x = 0; x <= 40; ++x) {
      const double z = dg::sim::shape_height_mm(dg::sim::PartKind::kDome, x, y) + noise_mm();
      measured.push_back({static_cast<double>(x), static_cast<double>(y), std::round(z * 1000) / 1000});
    }
  const Alignment r = align_to_nominal(measured, [&](const Point3& p) { return nominal.closest(p); });
  CHECK(r.rms_after_mm <= r.rms_before_mm * 1.01);
  CHECK(norm(r.transform.translation) < 0.002);
}
