// STL and OBJ nominals: our own writers' files read back, the formats' variants, errors that name
// the place, and a mesh nominal that measures as the surface it was made from.
#include "host/cad/mesh_reader.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <string>

#include "host/cad/mesh_writer.h"
#include "host/geometry/triangle_mesh.h"
#include "host/inspect/inspect.h"
#include "tests/support/sample_surfaces.h"

using namespace dg::host;

namespace {

Mesh stl_of(const std::string& bytes) {
  return parse_stl(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), "part.stl");
}

std::string error_of_stl(const std::string& bytes) {
  try {
    stl_of(bytes);
  } catch (const MeshFileError& e) {
    return e.what();
  }
  return "";
}

std::string error_of_obj(const std::string& text) {
  try {
    parse_obj(text, "part.obj");
  } catch (const MeshFileError& e) {
    return e.what();
  }
  return "";
}

const char* kAsciiTetrahedron =
    "solid tetra\n"
    " facet normal 0 0 -1\n  outer loop\n   vertex 0 0 0\n   vertex 0 1 0\n   vertex 1 0 0\n  endloop\n endfacet\n"
    " facet normal 0 -1 0\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 0 1\n  endloop\n endfacet\n"
    " facet normal -1 0 0\n  outer loop\n   vertex 0 0 0\n   vertex 0 0 1\n   vertex 0 1 0\n  endloop\n endfacet\n"
    " facet normal 1 1 1\n  outer loop\n   vertex 1 0 0\n   vertex 0 1 0\n   vertex 0 0 1.0e0\n  endloop\n endfacet\n"
    "endsolid tetra\n";

}  // namespace

TEST_GROUP(MeshReader){};

TEST(MeshReader, OurBinaryStlAndObjReadBackWithTheirCornersShared) {
  const Mesh written = tessellate(dg::test::clamped_sample(), 0.01);
  for (const Mesh& read : {stl_of(stl_bytes(written)), parse_obj(obj_text(written), "part.obj")}) {
    LONGS_EQUAL(written.triangles.size(), read.triangles.size());
    // STL repeats each corner per triangle: welded, the vertices are the grid's again.
    LONGS_EQUAL(written.vertices.size(), read.vertices.size());
    for (size_t t = 0; t < read.triangles.size(); t += 97) {
      for (int k = 0; k < 3; ++k) {
        const Point3 a = written.vertices[written.triangles[t][k]], b = read.vertices[read.triangles[t][k]];
        DOUBLES_EQUAL(a.x, b.x, 1e-5 * (1 + std::fabs(a.x)));  // STL stores float32
        DOUBLES_EQUAL(a.z, b.z, 1e-5 * (1 + std::fabs(a.z)));
      }
    }
  }
}

TEST(MeshReader, AsciiStlAndABinaryStlWhoseHeaderSaysSolid) {
  const Mesh ascii = stl_of(kAsciiTetrahedron);
  LONGS_EQUAL(4, ascii.triangles.size());
  LONGS_EQUAL(4, ascii.vertices.size());
  std::string binary = stl_bytes(ascii);
  binary.replace(0, 5, "solid");
  const Mesh read = stl_of(binary);
  LONGS_EQUAL(4, read.triangles.size());
  // The tetrahedron's corners wound outward: a point inside is on the negative side.
  const MeshLocator locator(read);
  CHECK(locator.closest({0.1, 0.1, 0.1}).distance < 0);
  CHECK(locator.closest({1, 1, 1}).distance > 0);
}

TEST(MeshReader, ObjFacesInEveryIndexFormPolygonsAsFansAndNegativeIndices) {
  const Mesh m = parse_obj("# a unit square and a triangle\nmtllib x.mtl\no part\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\n"
                           "vt 0 0\nvn 0 0 1\ns off\nf 1/1/1 2/1/1 3/1/1 4/1/1\nv 2 0 0\nf -1 2//1 -3\nl 1 2\n",
                           "part.obj");
  LONGS_EQUAL(5, m.vertices.size());
  LONGS_EQUAL(3, m.triangles.size());
  LONGS_EQUAL(4, m.triangles[2][0]);  // -1: the last vertex so far
  LONGS_EQUAL(2, m.triangles[2][2]);  // -3
}

TEST(MeshReader, ErrorsNameTheFileAndThePlace) {
  STRCMP_CONTAINS("part.stl: line 4: `0,5` is not a number", error_of_stl("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0,5 0 0\n").c_str());
  STRCMP_CONTAINS("a facet with 2 vertices", error_of_stl("solid x\nfacet\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n").c_str());
  STRCMP_CONTAINS("ends inside a facet", error_of_stl("solid x\nfacet\nouter loop\nvertex 0 0 0\n").c_str());
  STRCMP_CONTAINS("neither a binary STL", error_of_stl(std::string(84 + 49, '\0')).c_str());
  STRCMP_CONTAINS("not a finite number", error_of_stl("solid x\nfacet\nouter loop\nvertex 0 0 nan\n").c_str());
  STRCMP_CONTAINS("holds no triangles", error_of_stl("solid empty\nendsolid empty\n").c_str());
  STRCMP_CONTAINS("part.obj: line 3: vertex 4 is not among the 2", error_of_obj("v 0 0 0\nv 1 0 0\nf 1 2 4\n").c_str());
  STRCMP_CONTAINS("line 2: `0/1` is not a vertex index", error_of_obj("v 0 0 0\nf 0/1 1 1\n").c_str());
  STRCMP_CONTAINS("at least three corners", error_of_obj("v 0 0 0\nv 1 0 0\nf 1 2\n").c_str());
  STRCMP_CONTAINS("`curv` is not an OBJ statement", error_of_obj("curv 0 1 2\n").c_str());
}

TEST(MeshReader, AMeshNominalMeasuresAsTheSurfaceItWasMadeFrom) {
  // Points 0.05 mm either side of a surface, measured against the surface and against its STL to
  // a 0.5 um chord: the two agree to within the chord.
  const BSplineSurface surface = dg::test::clamped_sample();
  const Mesh mesh = stl_of(stl_bytes(tessellate(surface, 0.0005)));
  std::vector<Point3> points;
  for (int i = 0; i <= 20; ++i) {
    for (int j = 0; j <= 20; ++j) {
      Point3 p = surface.evaluate(surface.u_min() + (surface.u_max() - surface.u_min()) * i / 20.0,
                                  surface.v_min() + (surface.v_max() - surface.v_min()) * j / 20.0);
      p.z += (i + j) % 2 ? 0.05 : -0.05;
      points.push_back(p);
    }
  }
  const Inspection exact = inspect(points, surface, {});
  const MeshLocator locator(mesh);
  const Inspection meshed = inspect_nominal(points, [&](const Point3& p) { return locator.closest(p); }, {});
  for (size_t k = 0; k < points.size(); ++k) DOUBLES_EQUAL(exact.points[k].distance, meshed.points[k].distance, 0.0006);
}
