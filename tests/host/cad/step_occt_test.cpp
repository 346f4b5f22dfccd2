// Our STEP read by a real CAD kernel: OpenCASCADE's STEP reader must accept the file and build one
// face whose surface evaluates to ours (relative 1e-9), for a fitted net and a device's unclamped net;
// and our STEP reader must read what OpenCASCADE writes.
#include <CppUTest/TestHarness.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRep_Tool.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <STEPControl_Reader.hxx>
#include <STEPControl_Writer.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <cmath>
#include <cstdio>
#include <string>
#include <unistd.h>
#include <vector>

#include "host/surface/step_reader.h"
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

TEST(StepOcct, OpenCascadeReadsABezierPatch) { check_round_trip(dg::test::bezier_sample()); }

TEST(StepOcct, OurReaderReadsAStepFileOpenCascadeWrote) {
  // A surface built in OCCT (our sample's poles and knots), written by OCCT's STEP writer, read by
  // ours: a foreign file, not our own writer's layout.
  const BSplineSurface ours = dg::test::clamped_sample();
  TColgp_Array2OfPnt poles(1, ours.count_u, 1, ours.count_v);
  for (int i = 0; i < ours.count_u; ++i)
    for (int j = 0; j < ours.count_v; ++j) poles.SetValue(i + 1, j + 1, gp_Pnt(ours.at(i, j).x, ours.at(i, j).y, ours.at(i, j).z));
  auto distinct = [](const std::vector<double>& knots, TColStd_Array1OfReal*& values, TColStd_Array1OfInteger*& mults) {
    std::vector<double> v;
    std::vector<int> m;
    for (double k : knots) {
      if (!v.empty() && v.back() == k) ++m.back();
      else {
        v.push_back(k);
        m.push_back(1);
      }
    }
    values = new TColStd_Array1OfReal(1, static_cast<int>(v.size()));
    mults = new TColStd_Array1OfInteger(1, static_cast<int>(v.size()));
    for (size_t k = 0; k < v.size(); ++k) {
      values->SetValue(static_cast<int>(k) + 1, v[k]);
      mults->SetValue(static_cast<int>(k) + 1, m[k]);
    }
  };
  TColStd_Array1OfReal *uk = nullptr, *vk = nullptr;
  TColStd_Array1OfInteger *um = nullptr, *vm = nullptr;
  distinct(ours.knots_u, uk, um);
  distinct(ours.knots_v, vk, vm);
  const Handle(Geom_BSplineSurface) surface = new Geom_BSplineSurface(poles, *uk, *vk, *um, *vm, ours.degree_u, ours.degree_v);
  delete uk;
  delete vk;
  delete um;
  delete vm;
  const TopoDS_Face face = BRepBuilderAPI_MakeFace(surface, 1e-7);
  STEPControl_Writer writer;
  CHECK_EQUAL(IFSelect_RetDone, writer.Transfer(face, STEPControl_AsIs));
  const std::string path = std::string(P_tmpdir) + "/dg_occt_" + std::to_string(getpid()) + ".stp";
  CHECK_EQUAL(IFSelect_RetDone, writer.Write(path.c_str()));
  const BSplineSurface back = read_step_surface(path);
  std::remove(path.c_str());
  for (int a = 0; a <= 10; ++a)
    for (int b = 0; b <= 10; ++b) {
      const Point3 p = ours.evaluate(a / 10.0, b / 10.0), q = back.evaluate(a / 10.0, b / 10.0);
      DOUBLES_EQUAL(p.x, q.x, 1e-9);
      DOUBLES_EQUAL(p.y, q.y, 1e-9);
      DOUBLES_EQUAL(p.z, q.z, 1e-9);
    }
}
