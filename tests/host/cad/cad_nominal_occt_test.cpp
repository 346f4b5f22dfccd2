// CAD parts as nominals through OpenCASCADE: a box, a cylinder and a box written in inches, built
// by OpenCASCADE's own modelling and written by its own STEP and IGES writers; every point's signed
// distance against the solid's true one (positive outside), at faces, edges and corners.
#include <CppUTest/TestHarness.h>

#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Writer.hxx>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <unistd.h>

#include "host/cad/cad_nominal.h"
#include "host/cad/step_writer.h"
#include "host/fit/regions.h"
#include "host/geometry/surface_locator.h"
#include "host/geometry/vec3.h"
#include "tests/support/part_scan.h"
#include "tests/support/sample_surfaces.h"

using namespace dg::host;

namespace {

std::string temporary(const char* name) { return std::string(P_tmpdir) + "/dg_nominal_" + std::to_string(getpid()) + "_" + name; }

void write_step(const TopoDS_Shape& shape, const std::string& path, const char* unit = "MM") {
  Interface_Static::SetCVal("write.step.unit", unit);
  STEPControl_Writer writer;
  CHECK_EQUAL(IFSelect_RetDone, writer.Transfer(shape, STEPControl_AsIs));
  CHECK_EQUAL(IFSelect_RetDone, writer.Write(path.c_str()));
  Interface_Static::SetCVal("write.step.unit", "MM");
}

// The true signed distance to the box [0, 40] x [0, 30] x [0, 10] mm.
double box_distance(const Point3& p) {
  const double dx = std::max({-p.x, p.x - 40, 0.0}), dy = std::max({-p.y, p.y - 30, 0.0}), dz = std::max({-p.z, p.z - 10, 0.0});
  const double outside = std::sqrt(dx * dx + dy * dy + dz * dz);
  return outside > 0 ? outside : -std::min({p.x, 40 - p.x, p.y, 30 - p.y, p.z, 10 - p.z});
}

// The true signed distance to a cylinder of radius 10 about the z axis, z in [0, 20].
double cylinder_distance(const Point3& p) {
  const double radial = std::hypot(p.x, p.y) - 10, axial = std::max(-p.z, p.z - 20);
  const double outside = std::hypot(std::max(radial, 0.0), std::max(axial, 0.0));
  return outside > 0 ? outside : std::max(radial, axial);
}

template <class Truth>
double worst_error(const CadNominal& nominal, Truth truth, Point3 low, Point3 high, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(low.x, high.x), y(low.y, high.y), z(low.z, high.z);
  double worst = 0;
  for (int k = 0; k < 300; ++k) {
    const Point3 p{x(rng), y(rng), z(rng)};
    const Closest c = nominal.closest(p);
    worst = std::max(worst, std::fabs(c.distance - truth(p)));
    // A solid's every edge bounds two faces (a cylinder's seam bounds its one face twice): no border.
    CHECK_FALSE(c.on_border);
  }
  return worst;
}

}  // namespace

TEST_GROUP(CadNominal){};

TEST(CadNominal, ABoxFromStepMeasuresAsTheTrueSolidAtFacesEdgesAndCorners) {
  const std::string path = temporary("box.stp");
  write_step(BRepPrimAPI_MakeBox(40, 30, 10).Shape(), path);
  const std::unique_ptr<CadNominal> nominal = CadNominal::read(path);
  LONGS_EQUAL(6, nominal->face_count());
  const double worst = worst_error(*nominal, box_distance, {-5, -5, -5}, {45, 35, 15}, 1);
  std::printf("\n  box (STEP, 6 faces): worst |distance - true| %.2g mm", worst);
  CHECK(worst < 1e-6);
  LONGS_EQUAL(0, nominal->mesh_fallbacks());
  std::remove(path.c_str());
}

TEST(CadNominal, ACylinderFromIgesMeasuresAsTheTrueSolid) {
  const std::string path = temporary("cylinder.igs");
  IGESControl_Controller::Init();
  IGESControl_Writer writer("MM", 1);  // faces as B-rep entities (186)
  writer.AddShape(BRepPrimAPI_MakeCylinder(10, 20).Shape());
  writer.ComputeModel();
  CHECK(writer.Write(path.c_str()));
  const std::unique_ptr<CadNominal> nominal = CadNominal::read(path);
  CHECK(nominal->face_count() >= 3);
  const double worst = worst_error(*nominal, cylinder_distance, {-14, -14, -4}, {14, 14, 24}, 2);
  std::printf("\n  cylinder (IGES, %zu faces): worst |distance - true| %.2g mm", nominal->face_count(), worst);
  CHECK(worst < 1e-5);
  std::remove(path.c_str());
}

TEST(CadNominal, APartWrittenInInchesIsMeasuredInMillimetres) {
  const std::string path = temporary("box-inch.stp");
  write_step(BRepPrimAPI_MakeBox(40, 30, 10).Shape(), path, "INCH");
  std::ifstream written(path);
  const std::string text((std::istreambuf_iterator<char>(written)), std::istreambuf_iterator<char>());
  CHECK(text.find("INCH") != std::string::npos);
  const std::unique_ptr<CadNominal> nominal = CadNominal::read(path);
  CHECK(worst_error(*nominal, box_distance, {-5, -5, -5}, {45, 35, 15}, 3) < 1e-6);
  std::remove(path.c_str());
}

TEST(CadNominal, ADamagedOrEmptyFileIsRefusedNamingIt) {
  const std::string path = temporary("damaged.stp");
  std::ofstream(path) << "ISO-10303-21;\nHEADER;\nthis is not STEP\n";
  try {
    CadNominal::read(path);
    FAIL("a damaged STEP file was read");
  } catch (const CadNominalError& e) {
    STRCMP_CONTAINS(path.c_str(), e.what());
  }
  std::remove(path.c_str());
  CHECK_THROWS(CadNominalError, CadNominal::read(temporary("missing.stp")));
}

TEST(CadNominal, ABsplineFaceMeasuresAsOurOwnSurfaceDoes) {
  // Our STEP of a B-spline surface read back by OpenCASCADE: Newton from the mesh foot on the face,
  // or the global search near its edges, gives the distance our own closest-point code finds.
  const BSplineSurface surface = dg::test::clamped_sample();
  const std::string path = temporary("bspline.stp");
  dg::host::write_step(path, surface, StepOptions{});
  const std::unique_ptr<CadNominal> nominal = CadNominal::read(path);
  const SurfaceLocator locator(surface);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> at(0.05, 0.95), off(-0.3, 0.3);
  double worst = 0;
  for (int k = 0; k < 300; ++k) {
    Point3 p = surface.evaluate(at(rng), at(rng));
    p.z += off(rng);
    worst = std::max(worst, std::fabs(nominal->closest(p).distance - locator.closest(p).distance));
  }
  std::printf("\n  B-spline face (STEP): worst |distance - ours| %.2g mm", worst);
  CHECK(worst < 1e-6);
  LONGS_EQUAL(0, nominal->mesh_fallbacks());
  std::remove(path.c_str());
}

TEST(CadNominal, AFootOffToTheSideOfASingleFacesEdgeIsOnItsBorder) {
  // A single face (our STEP of a B-spline surface, an open shell) has a border: a point off to the
  // side of it finds its foot there, as our own closest point, clamped to the domain, does (the
  // solids mark none: worst_error).
  const BSplineSurface surface = dg::test::clamped_sample();
  const std::string path = temporary("border.stp");
  dg::host::write_step(path, surface, StepOptions{});
  const std::unique_ptr<CadNominal> nominal = CadNominal::read(path);
  const SurfaceLocator locator(surface);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> x(-8, 49), y(-8, 38), z(0, 5);
  int compared = 0, on_border = 0;
  for (int k = 0; k < 300; ++k) {
    const Point3 p{x(rng), y(rng), z(rng)};
    const Closest ours = locator.closest(p);
    // Where the point is nearly over the edge either answer is right: left out.
    const Point3 r = p - ours.point;
    if (ours.on_border && norm(r - dot(r, ours.normal) * ours.normal) < 0.05) continue;
    ++compared;
    on_border += ours.on_border;
    CHECK_EQUAL(ours.on_border, nominal->closest(p).on_border);
  }
  std::printf("\n  B-spline face (STEP): %d of %d points off to the side of its edge", on_border, compared);
  CHECK(compared > 250);
  CHECK(on_border > 50 && on_border < compared - 50);
  std::remove(path.c_str());
}

TEST(CadNominal, AnUnsewnBoxFromIgesHasNoBorder) {
  // IGES as many CAD programs write it: each face a trimmed surface (entity 144) with edges of its
  // own. Each edge runs along the neighbouring face's edge, so the box is closed and marks no point.
  const std::string path = temporary("unsewn.igs");
  IGESControl_Controller::Init();
  IGESControl_Writer writer("MM", 0);
  writer.AddShape(BRepPrimAPI_MakeBox(40, 30, 10).Shape());
  writer.ComputeModel();
  CHECK(writer.Write(path.c_str()));
  const std::unique_ptr<CadNominal> nominal = CadNominal::read(path);
  const double worst = worst_error(*nominal, box_distance, {-5, -5, -5}, {45, 35, 15}, 3);
  std::printf("\n  box (IGES, %zu trimmed surfaces): worst |distance - true| %.2g mm", nominal->face_count(), worst);
  CHECK(worst < 1e-5);
  std::remove(path.c_str());
}

TEST(CadNominal, OurTrimmedFacesMeetAtTheirSeamAndEndAtTheScansEdge) {
  // The dome fitted as trimmed faces (cap and plate, each with edges of its own) and written as STEP:
  // over the scanned area no foot is on a border, the seam between the faces included; off to the
  // side of the scan's edge every point's is.
  dg::test::PartScan dome;
  RegionOptions options;
  options.tolerance.tolerance_mm = 0.025;
  const RegionFit fit = fit_regions(dg::test::scan_part(dome, 3), nullptr, options);
  CHECK(fit.faces.size() >= 2);
  const std::string path = temporary("dome_faces.stp");
  write_step_faces(path, fit.faces, StepOptions{});
  const std::unique_ptr<CadNominal> nominal = CadNominal::read(path);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> x(0.5, 39.5), y(0.5, 29.5), off(-0.2, 0.2), out(3, 8);
  int inside_marked = 0;
  for (int k = 0; k < 400; ++k) {
    const double px = x(rng), py = y(rng);
    inside_marked += nominal->closest({px, py, dg::sim::shape_height_mm(dome.kind, px, py) + off(rng)}).on_border;
  }
  int beyond_marked = 0;
  for (int k = 0; k < 100; ++k) {
    const double py = y(rng);
    beyond_marked += nominal->closest({-out(rng), py, dg::sim::shape_height_mm(dome.kind, 0, py)}).on_border;
    beyond_marked += nominal->closest({40 + out(rng), py, dg::sim::shape_height_mm(dome.kind, 40, py)}).on_border;
  }
  std::printf("\n  dome as %zu trimmed faces (STEP): %d of 400 points over the scan and %d of 200 beyond its edge on a border",
              nominal->face_count(), inside_marked, beyond_marked);
  LONGS_EQUAL(0, inside_marked);
  LONGS_EQUAL(200, beyond_marked);
  std::remove(path.c_str());
}
