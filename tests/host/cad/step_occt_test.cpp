// Our STEP read by a real CAD kernel: OpenCASCADE's STEP reader must accept the file and build one
// face whose surface evaluates to ours (relative 1e-9), for a fitted net and a device's unclamped net.
#include <CppUTest/TestHarness.h>

#include <BRep_Tool.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <STEPControl_Reader.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <cmath>
#include <cstdio>
#include <string>
#include <unistd.h>

#include "host/surface/step_writer.h"
#include "tests/support/sample_surfaces.h"

using namespace dg::host;

namespace {

void check_round_trip(const BSplineSurface& ours) {
  const std::string path = std::string(P_tmpdir) + "/dg_step_" + std::to_string(getpid()) + ".stp";
  write_step(path, ours, StepOptions{});
  STEPControl_Reader reader;
  CHECK_EQUAL(IFSelect_RetDone, reader.ReadFile(path.c_str()));
  std::remove(path.c_str());
  CHECK(reader.TransferRoots() > 0);
  int faces = 0;
  Handle(Geom_BSplineSurface) theirs;
  for (TopExp_Explorer it(reader.OneShape(), TopAbs_FACE); it.More(); it.Next()) {
    ++faces;
    theirs = Handle(Geom_BSplineSurface)::DownCast(BRep_Tool::Surface(TopoDS::Face(it.Current())));
  }
  LONGS_EQUAL(1, faces);
  CHECK(!theirs.IsNull());
  double scale = 0;
  for (const Point3& p : ours.control) scale = std::fmax(scale, std::fmax(std::fabs(p.x), std::fmax(std::fabs(p.y), std::fabs(p.z))));
  for (int a = 0; a <= 20; ++a) {
    for (int b = 0; b <= 20; ++b) {
      const double u = ours.u_min() + (ours.u_max() - ours.u_min()) * a / 20.0;
      const double v = ours.v_min() + (ours.v_max() - ours.v_min()) * b / 20.0;
      const Point3 p = ours.evaluate(u, v);
      const gp_Pnt q = theirs->Value(u, v);
      DOUBLES_EQUAL(p.x, q.X(), 1e-9 * scale);
      DOUBLES_EQUAL(p.y, q.Y(), 1e-9 * scale);
      DOUBLES_EQUAL(p.z, q.Z(), 1e-9 * scale);
    }
  }
}

}  // namespace

TEST_GROUP(StepOcct){};

TEST(StepOcct, OpenCascadeReadsAFittedNetAsOneFace) { check_round_trip(dg::test::clamped_sample()); }

TEST(StepOcct, OpenCascadeReadsTheDevicesUnclampedNetAfterClamping) { check_round_trip(dg::test::unclamped_sample()); }
