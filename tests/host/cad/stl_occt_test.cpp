// Our binary STL read by OpenCASCADE's STL reader: every triangle, vertices where we put them.
#include <CppUTest/TestHarness.h>

#include <Poly_Triangulation.hxx>
#include <RWStl.hxx>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include "host/cad/mesh_writer.h"
#include "tests/support/sample_surfaces.h"

using namespace dg::host;

TEST_GROUP(StlOcct){};

TEST(StlOcct, OpenCascadeReadsEveryTriangle) {
  const Mesh mesh = tessellate(dg::test::clamped_sample(), 0.02);
  const std::string path = std::string(P_tmpdir) + "/dg_stl_" + std::to_string(getpid()) + ".stl";
  write_mesh(path, mesh);
  const Handle(Poly_Triangulation) theirs = RWStl::ReadFile(path.c_str());
  std::remove(path.c_str());
  CHECK(!theirs.IsNull());
  LONGS_EQUAL(mesh.triangles.size(), theirs->NbTriangles());
  // OCCT merges shared vertices; each of its nodes must be one of ours (float precision).
  for (int n = 1; n <= theirs->NbNodes(); n += 17) {
    const gp_Pnt q = theirs->Node(n);
    double nearest = HUGE_VAL;
    for (const Point3& p : mesh.vertices) nearest = std::fmin(nearest, std::hypot(p.x - q.X(), p.y - q.Y(), p.z - q.Z()));
    CHECK(nearest < 1e-4);
  }
}

// A vertex a 32-bit float cannot hold is refused, and nothing is written.
TEST(StlOcct, RefusesAVertexBeyondAFloatsRange) {
  Mesh mesh = tessellate(dg::test::clamped_sample(), 0.05);
  mesh.vertices[3].z = 1e300;
  const std::string path = std::string(P_tmpdir) + "/dg_stl_huge_" + std::to_string(getpid()) + ".stl";
  std::remove(path.c_str());
  CHECK_THROWS(std::invalid_argument, write_mesh(path, mesh));
  CHECK(access(path.c_str(), F_OK) != 0);
}
