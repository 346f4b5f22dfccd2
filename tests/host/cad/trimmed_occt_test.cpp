// Trimmed faces read by a real CAD kernel: OpenCASCADE reads our IGES (entity 144) and STEP (an open
// shell of advanced faces) as valid faces (BRepCheck), as many as we wrote, whose area is the true
// part's, and which pass within the tolerance of the true part between the samples.
#include <CppUTest/TestHarness.h>

#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <STEPControl_Reader.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <cmath>
#include <cstdio>
#include <string>
#include <unistd.h>

#include "host/cad/iges_writer.h"
#include "host/cad/step_writer.h"
#include "host/fit/regions.h"
#include "tests/support/part_scan.h"

using namespace dg::host;

namespace {

constexpr double kTolerance = 0.025;

const dg::test::PartScan& dome() {
  static const dg::test::PartScan s = [] {
    dg::test::PartScan p;
    p.kind = dg::sim::PartKind::kDome;
    p.sigma_um = 5;
    return p;
  }();
  return s;
}

const RegionFit& fitted() {
  static const RegionFit r = [] {
    RegionOptions o;
    o.tolerance.tolerance_mm = kTolerance;
    return fit_regions(dg::test::scan_part(dome(), 3), nullptr, o);
  }();
  return r;
}

// The dome's true area over the scanned rectangle, by the midpoint rule on a 0.05 mm grid.
double true_area() {
  const double h = 0.05, d = 1e-5;
  double area = 0;
  for (double x = h / 2; x < 40; x += h) {
    for (double y = h / 2; y < 30; y += h) {
      const double zx = (dg::sim::shape_height_mm(dome().kind, x + d, y) - dg::sim::shape_height_mm(dome().kind, x - d, y)) / (2 * d);
      const double zy = (dg::sim::shape_height_mm(dome().kind, x, y + d) - dg::sim::shape_height_mm(dome().kind, x, y - d)) / (2 * d);
      area += std::sqrt(1 + zx * zx + zy * zy) * h * h;
    }
  }
  return area;
}

void check_shape(const TopoDS_Shape& shape) {
  CHECK(!shape.IsNull());
  int faces = 0;
  for (TopExp_Explorer it(shape, TopAbs_FACE); it.More(); it.Next()) {
    ++faces;
    CHECK(BRepCheck_Analyzer(it.Current()).IsValid());
  }
  LONGS_EQUAL(static_cast<long>(fitted().faces.size()), faces);
  CHECK(BRepCheck_Analyzer(shape).IsValid());
  GProp_GProps props;
  // Adaptive integration: the fixed Gauss rule misjudges faces whose trims cut the knot spans.
  BRepGProp::SurfaceProperties(shape, props, 1e-6);
  const double area = true_area();
  DOUBLES_EQUAL(area, props.Mass(), 0.005 * area);
  // Between the samples (half a step off every grid line), across the rim and the plate's corners.
  for (double x = 0.5; x < 40; x += 3) {
    for (double y = 0.5; y < 30; y += 3) {
      const gp_Pnt p(x, y, dg::sim::shape_height_mm(dome().kind, x, y));
      BRepExtrema_DistShapeShape distance(BRepBuilderAPI_MakeVertex(p).Vertex(), shape);
      CHECK(distance.IsDone());
      CHECK(distance.Value() <= kTolerance);
    }
  }
}

std::string temp_path(const char* extension) {
  return std::string(P_tmpdir) + "/dg_trimmed_" + std::to_string(getpid()) + extension;
}

// Writes the dome's faces, has OpenCASCADE read them with `Reader` and checks the shape.
template <class Reader, class Write>
void check_written(const char* extension, Write write) {
  CHECK(fitted().kept);
  const std::string path = temp_path(extension);
  write(path);
  Reader reader;
  CHECK_EQUAL(IFSelect_RetDone, reader.ReadFile(path.c_str()));
  std::remove(path.c_str());
  CHECK(reader.TransferRoots() > 0);
  check_shape(reader.OneShape());
}

}  // namespace

TEST_GROUP(TrimmedOcct){};

TEST(TrimmedOcct, OpenCascadeReadsTheDomesTrimmedFacesFromIgesAsValidFacesOfTheTrueArea) {
  check_written<IGESControl_Reader>(".igs", [](const std::string& path) { write_iges_faces(path, fitted().faces, IgesOptions{}); });
}

TEST(TrimmedOcct, OpenCascadeReadsTheDomesTrimmedFacesFromStepAsValidFacesOfTheTrueArea) {
  check_written<STEPControl_Reader>(".stp", [](const std::string& path) { write_step_faces(path, fitted().faces, StepOptions{}); });
}
