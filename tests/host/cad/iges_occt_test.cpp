// Our IGES read by a real CAD kernel: OpenCASCADE's IGES reader must accept the file, and the
// surface it builds must evaluate to our surface's points (relative 1e-9).
#include <CppUTest/TestHarness.h>

#include <BRep_Tool.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESData_GlobalSection.hxx>
#include <IGESData_IGESModel.hxx>
#include <TCollection_HAsciiString.hxx>
#include <Standard_Version.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <cmath>
#include <cstdio>
#include <string>
#include <unistd.h>

#include "host/cad/iges_writer.h"
#include "tests/host/cad/occt_compare.h"
#include "tests/support/sample_surfaces.h"

using namespace dg::host;

namespace {

Handle(Geom_BSplineSurface) read_back(const std::string& path) {
  IGESControl_Reader reader;
  CHECK_EQUAL(IFSelect_RetDone, reader.ReadFile(path.c_str()));
  CHECK(reader.TransferRoots() > 0);
  const TopoDS_Shape shape = reader.OneShape();
  TopExp_Explorer faces(shape, TopAbs_FACE);
  CHECK(faces.More());
  const Handle(Geom_Surface) surface = BRep_Tool::Surface(TopoDS::Face(faces.Current()));
  const Handle(Geom_BSplineSurface) bspline = Handle(Geom_BSplineSurface)::DownCast(surface);
  CHECK(!bspline.IsNull());
  return bspline;
}

void check_round_trip(const BSplineSurface& ours) {
  const std::string path = std::string(P_tmpdir) + "/dg_iges_" + std::to_string(getpid()) + ".igs";
  IgesOptions options;
  options.file_name = "test.igs";
  write_iges(path, ours, options);
  const Handle(Geom_BSplineSurface) theirs = read_back(path);
  std::remove(path.c_str());
  LONGS_EQUAL(ours.degree_u, theirs->UDegree());
  LONGS_EQUAL(ours.degree_v, theirs->VDegree());
  dg::test::check_evaluates_alike(ours, theirs);
}

}  // namespace

TEST_GROUP(IgesOcct){};

TEST(IgesOcct, OpenCascadeReadsAFittedNetAndEvaluatesItToOurPoints) { check_round_trip(dg::test::clamped_sample()); }

TEST(IgesOcct, OpenCascadeReadsTheDevicesUnclampedNet) { check_round_trip(dg::test::unclamped_sample()); }

TEST(IgesOcct, OpenCascadeReadsABezierPatch) { check_round_trip(dg::test::bezier_sample()); }

TEST(IgesOcct, WritesTheFixedColumnLayout) {
  const std::string text = iges_text(dg::test::clamped_sample(), IgesOptions{});
  size_t start = 0, lines = 0;
  while (start < text.size()) {
    const size_t end = text.find('\n', start);
    LONGS_EQUAL(80, end - start);
    ++lines;
    start = end + 1;
  }
  CHECK(lines > 6);
  STRCMP_CONTAINS("2HMM", text.c_str());
  STRCMP_EQUAL("3.", iges_real(3.0).c_str());
  STRCMP_EQUAL("1.E-05", iges_real(1e-5).c_str());
  STRCMP_EQUAL("0.1", iges_real(0.1).c_str());
}

TEST(IgesOcct, OpenCascadeReadsThePartsName) {
  const std::string path = std::string(P_tmpdir) + "/dg_iges_name_" + std::to_string(getpid()) + ".igs";
  IgesOptions options;
  options.product = "bracket rev 2";
  write_iges(path, dg::test::clamped_sample(), options);
  IGESControl_Reader reader;
  CHECK_EQUAL(IFSelect_RetDone, reader.ReadFile(path.c_str()));
  std::remove(path.c_str());
  const IGESData_GlobalSection& global = reader.IGESModel()->GlobalSection();
  STRCMP_EQUAL("bracket rev 2", global.SendName()->ToCString());
  STRCMP_EQUAL("bracket rev 2", global.ReceiveName()->ToCString());
}
