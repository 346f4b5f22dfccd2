// Our STEP read by a real CAD kernel: OpenCASCADE's STEP reader must accept the file and build one
// face whose surface evaluates to ours (relative 1e-9), for a fitted net and a device's unclamped net;
// and our STEP reader must read what OpenCASCADE writes.
#include <CppUTest/TestHarness.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRep_Tool.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <STEPControl_Reader.hxx>
#include <StepBasic_Product.hxx>
#include <StepData_StepModel.hxx>
#include <TCollection_HAsciiString.hxx>
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

#include "host/cad/step_reader.h"
#include "host/cad/step_writer.h"
#include "tests/host/cad/occt_compare.h"
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
  dg::test::check_evaluates_alike(ours, theirs);
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
  // OCCT takes distinct knots and their multiplicities.
  auto distinct = [](const std::vector<double>& knots, std::vector<double>& values, std::vector<int>& mults) {
    for (double k : knots) {
      if (!values.empty() && values.back() == k) {
        ++mults.back();
      } else {
        values.push_back(k);
        mults.push_back(1);
      }
    }
  };
  std::vector<double> u_values, v_values;
  std::vector<int> u_mults, v_mults;
  distinct(ours.knots_u, u_values, u_mults);
  distinct(ours.knots_v, v_values, v_mults);
  TColStd_Array1OfReal uk(1, static_cast<int>(u_values.size())), vk(1, static_cast<int>(v_values.size()));
  TColStd_Array1OfInteger um(1, static_cast<int>(u_mults.size())), vm(1, static_cast<int>(v_mults.size()));
  for (size_t k = 0; k < u_values.size(); ++k) {
    uk.SetValue(static_cast<int>(k) + 1, u_values[k]);
    um.SetValue(static_cast<int>(k) + 1, u_mults[k]);
  }
  for (size_t k = 0; k < v_values.size(); ++k) {
    vk.SetValue(static_cast<int>(k) + 1, v_values[k]);
    vm.SetValue(static_cast<int>(k) + 1, v_mults[k]);
  }
  const Handle(Geom_BSplineSurface) surface = new Geom_BSplineSurface(poles, uk, vk, um, vm, ours.degree_u, ours.degree_v);
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

TEST(StepOcct, OpenCascadeReadsThePartsName) {
  const std::string path = std::string(P_tmpdir) + "/dg_step_name_" + std::to_string(getpid()) + ".stp";
  StepOptions options;
  options.product = "bracket 'B' \\ rev 2";
  write_step(path, dg::test::clamped_sample(), options);
  STEPControl_Reader reader;
  CHECK_EQUAL(IFSelect_RetDone, reader.ReadFile(path.c_str()));
  std::remove(path.c_str());
  const Handle(StepData_StepModel) model = reader.StepModel();
  std::string name;
  for (int i = 1; i <= model->NbEntities(); ++i) {
    const Handle(StepBasic_Product) product = Handle(StepBasic_Product)::DownCast(model->Value(i));
    if (!product.IsNull()) name = product->Name()->ToCString();
  }
  STRCMP_EQUAL("bracket 'B' \\ rev 2", name.c_str());
}
