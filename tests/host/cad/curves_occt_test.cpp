// Our curves read by OpenCASCADE: IGES entity 126 and STEP B_SPLINE_CURVE_WITH_KNOTS come back as
// edges whose curves evaluate to ours (relative 1e-9); here the four edges of a surface.
#include <CppUTest/TestHarness.h>

#include <BRep_Tool.hxx>
#include <Geom_BSplineCurve.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <STEPControl_Reader.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <cmath>
#include <cstdio>
#include <string>
#include <unistd.h>
#include <vector>

#include "host/geometry/bspline_curve.h"
#include "host/geometry/clamp.h"
#include "host/cad/iges_writer.h"
#include "host/cad/step_writer.h"
#include "tests/support/sample_surfaces.h"

using namespace dg::host;

namespace {

std::vector<Handle(Geom_BSplineCurve)> edges_of(const TopoDS_Shape& shape) {
  std::vector<Handle(Geom_BSplineCurve)> out;
  for (TopExp_Explorer it(shape, TopAbs_EDGE); it.More(); it.Next()) {
    double first = 0, last = 0;
    out.push_back(Handle(Geom_BSplineCurve)::DownCast(BRep_Tool::Curve(TopoDS::Edge(it.Current()), first, last)));
  }
  return out;
}

void check_same(const std::vector<BSplineCurve>& ours, const std::vector<Handle(Geom_BSplineCurve)>& theirs) {
  LONGS_EQUAL(ours.size(), theirs.size());
  for (size_t c = 0; c < ours.size(); ++c) {
    CHECK(!theirs[c].IsNull());
    for (int k = 0; k <= 20; ++k) {
      const double t = ours[c].t_min() + (ours[c].t_max() - ours[c].t_min()) * k / 20.0;
      const Point3 p = ours[c].evaluate(t);
      const gp_Pnt q = theirs[c]->Value(t);
      DOUBLES_EQUAL(p.x, q.X(), 1e-9 * 50);
      DOUBLES_EQUAL(p.y, q.Y(), 1e-9 * 50);
      DOUBLES_EQUAL(p.z, q.Z(), 1e-9 * 50);
    }
  }
}

}  // namespace

TEST_GROUP(CurvesOcct){};

TEST(CurvesOcct, IgesEntity126ComesBackAsEdges) {
  const std::vector<BSplineCurve> ours = boundary_curves(clamp_ends(dg::test::unclamped_sample()));
  const std::string path = std::string(P_tmpdir) + "/dg_curves_" + std::to_string(getpid()) + ".igs";
  write_iges_curves(path, ours, IgesOptions{});
  IGESControl_Reader reader;
  CHECK_EQUAL(IFSelect_RetDone, reader.ReadFile(path.c_str()));
  std::remove(path.c_str());
  CHECK(reader.TransferRoots() > 0);
  check_same(ours, edges_of(reader.OneShape()));
}

TEST(CurvesOcct, StepCurveSetComesBackAsEdges) {
  const std::vector<BSplineCurve> ours = boundary_curves(dg::test::clamped_sample());
  const std::string path = std::string(P_tmpdir) + "/dg_curves_" + std::to_string(getpid()) + ".stp";
  write_step_curves(path, ours, StepOptions{});
  STEPControl_Reader reader;
  CHECK_EQUAL(IFSelect_RetDone, reader.ReadFile(path.c_str()));
  std::remove(path.c_str());
  CHECK(reader.TransferRoots() > 0);
  check_same(ours, edges_of(reader.OneShape()));
}
