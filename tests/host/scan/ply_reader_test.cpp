// PLY reading: ASCII and both binary byte orders, skipped elements, and errors that name the place.
#include "host/scan/ply_reader.h"
#include "host/scan/point_export.h"

#include <CppUTest/TestHarness.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

dg::host::PointCloud read(const std::string& bytes) {
  return dg::host::parse_ply_points(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), "in.ply");
}

std::string error_of(const std::string& bytes) {
  try {
    read(bytes);
  } catch (const dg::host::PointFileError& e) {
    return e.what();
  }
  return "";
}

template <typename T>
void put(std::string& out, T value, bool big_endian) {
  char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if (big_endian) {
    for (size_t i = 0; i < sizeof(T); ++i) out.push_back(b[sizeof(T) - 1 - i]);
  } else {
    out.append(b, sizeof(T));
  }
}

// Two vertices (float x, double y, short z, uchar red) and one triangle face after them.
std::string binary_ply(bool big_endian) {
  std::string s = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\ncomment made by a test\nelement vertex 2\nproperty float x\nproperty double y\n"
                  "property short z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\n"
                  "end_header\n";
  put<float>(s, 1.5f, big_endian);
  put<double>(s, -2.25, big_endian);
  put<int16_t>(s, -7, big_endian);
  put<uint8_t>(s, 200, big_endian);
  put<float>(s, 3.0f, big_endian);
  put<double>(s, 4.0, big_endian);
  put<int16_t>(s, 9, big_endian);
  put<uint8_t>(s, 10, big_endian);
  put<uint8_t>(s, 3, big_endian);
  for (int32_t i : {0, 1, 0}) put<int32_t>(s, i, big_endian);
  return s;
}

}  // namespace

TEST_GROUP(PlyReader){};

TEST(PlyReader, ReadsAsciiVerticesWithNormalsAndSkipsFaces) {
  const dg::host::PointCloud c = read(
      "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n"
      "property float nx\r\nproperty float ny\r\nproperty float nz\r\nelement face 1\r\n"
      "property list uchar int vertex_indices\r\nend_header\r\n"
      "0 0 1.25 0 0 1\r\n1 0 2 0 0 1\r\n0 1 -3e-1 0 0 1\r\n3 0 1 2\r\n");
  LONGS_EQUAL(3, c.points.size());
  DOUBLES_EQUAL(1.25, c.points[0].z, 0);
  DOUBLES_EQUAL(-0.3, c.points[2].z, 1e-15);
  CHECK(c.normal.has_value());
  DOUBLES_EQUAL(1.0, (*c.normal)[1].z, 0);
}

TEST(PlyReader, ReadsLittleEndianBinaryOfMixedTypes) {
  const dg::host::PointCloud c = read(binary_ply(false));
  LONGS_EQUAL(2, c.points.size());
  DOUBLES_EQUAL(1.5, c.points[0].x, 0);
  DOUBLES_EQUAL(-2.25, c.points[0].y, 0);
  DOUBLES_EQUAL(-7, c.points[0].z, 0);
  DOUBLES_EQUAL(9, c.points[1].z, 0);
  CHECK_FALSE(c.normal.has_value());
}

TEST(PlyReader, ReadsBigEndianBinaryTheSame) {
  const dg::host::PointCloud little = read(binary_ply(false));
  const dg::host::PointCloud big = read(binary_ply(true));
  for (size_t i = 0; i < 2; ++i) {
    DOUBLES_EQUAL(little.points[i].x, big.points[i].x, 0);
    DOUBLES_EQUAL(little.points[i].y, big.points[i].y, 0);
    DOUBLES_EQUAL(little.points[i].z, big.points[i].z, 0);
  }
}

TEST(PlyReader, SkipsElementsBeforeTheVertices) {
  const dg::host::PointCloud c = read(
      "ply\nformat ascii 1.0\nelement camera 1\nproperty float view_px\nproperty list uchar float k\n"
      "element vertex 1\nproperty double x\nproperty double y\nproperty double z\nend_header\n"
      "0.5 3 7 8 9\n1 2 3\n");
  LONGS_EQUAL(1, c.points.size());
  DOUBLES_EQUAL(3, c.points[0].z, 0);
}

TEST(PlyReader, NamesWhatIsWrongAndWhere) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  STRCMP_CONTAINS("in.ply:9: 'z' is not a finite decimal number: 'nan'", error_of(head + "1 2 3\n4 5 nan\n").c_str());
  STRCMP_CONTAINS("in.ply:10: a row after the elements the header counts", error_of(head + "1 2 3\n4 5 6\n7 8 9\n").c_str());
  STRCMP_CONTAINS("in.ply:9: file ends before 'z'", error_of(head + "1 2 3\n4 5\n").c_str());
  STRCMP_CONTAINS("in.ply:9: 'y' is not a finite decimal number: 'a'", error_of(head + "1 2 3\n4 a 6\n").c_str());
  STRCMP_CONTAINS("in.ply:9: the same point as in.ply:8", error_of(head + "1 2 3\n1 2 3\n").c_str());
  STRCMP_CONTAINS("not a PLY file", error_of("solid x\n").c_str());
  STRCMP_CONTAINS("no end_header", error_of("ply\nformat ascii 1.0\n").c_str());
  STRCMP_CONTAINS("no 'z' property",
                  error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n").c_str());
  STRCMP_CONTAINS("unknown vertex property 'w'",
                  error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                           "property float z\nproperty float w\nend_header\n1 2 3 4\n").c_str());
  STRCMP_CONTAINS("in.ply:2: unknown PLY format 'binary'", error_of("ply\nformat binary 1.0\nend_header\n").c_str());
  std::string truncated = binary_ply(false);
  truncated.resize(truncated.size() - 20);
  STRCMP_CONTAINS("in.ply: file ends inside vertex 1", error_of(truncated).c_str());
  STRCMP_CONTAINS("header promises 1000000 vertices",
                  error_of("ply\nformat binary_little_endian 1.0\nelement vertex 1000000\nproperty float x\n"
                           "property float y\nproperty float z\nend_header\n").c_str());
}

// Found by the mesh reader's fuzzer: another element with more plain properties than the vertex
// element once wrote past the vertex's values; such a file is read (its other element skipped)
// or refused, never overrun. An element named twice is refused.
TEST(PlyReader, ALineOrSigmaOutOfItsRangeNamesTheVertex) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                           "property double line\nproperty double sigma\nend_header\n1 2 3 0 0.001\n";
  STRCMP_CONTAINS("in.ply:11 (vertex 1): line must be a whole number from 0 to 4294967294",
                  error_of(head + "4 5 6 2.5 0.001\n").c_str());
  STRCMP_CONTAINS("in.ply:11 (vertex 1): sigma must be from 0.000001 to 1000000 mm", error_of(head + "4 5 6 1 0\n").c_str());
  STRCMP_CONTAINS("in.ply:11 (vertex 1): 'z': coordinates and normals must lie within +-1000000 mm (1 km)",
                  error_of(head + "4 5 1e200 1 0.001\n").c_str());
}

TEST(PlyReader, AnElementWithMorePropertiesThanTheVertexIsSkippedSafely) {
  const std::string bytes =
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
      "element extra 1\nproperty list uchar int ids\nproperty float a\nproperty float b\nproperty float c\n"
      "property float d\nend_header\n1 2 3\n2 7 8 1 2 3 4\n";
  const dg::host::PointCloud cloud = read(bytes);
  LONGS_EQUAL(1, cloud.points.size());
  DOUBLES_EQUAL(3.0, cloud.points[0].z, 0);
  STRCMP_CONTAINS("element 'vertex' appears twice",
                  error_of("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nelement vertex 0\nend_header\n").c_str());
}

TEST(PlyReader, ReadsBackWhatExportWritesWithItsLines) {
  std::vector<dg::PointSample> samples(3);
  for (uint32_t i = 0; i < 3; ++i) {
    samples[i].line = i / 2;
    samples[i].x_nm = static_cast<int32_t>(i) * 1000000;
    samples[i].y_nm = 250000;
    samples[i].z_nm = -1234567 + static_cast<int32_t>(i);
  }
  const std::string path = "ply_reader_roundtrip.ply";
  dg::host::write_points_ply(path, samples);
  const dg::host::PointCloud c = dg::host::read_points(path);
  std::remove(path.c_str());
  LONGS_EQUAL(3, c.points.size());
  CHECK(c.line.has_value());
  LONGS_EQUAL(1, (*c.line)[2]);
  DOUBLES_EQUAL(2.0, c.points[2].x, 1e-12);
  DOUBLES_EQUAL(-1.234565, c.points[2].z, 1e-12);
}

namespace {

std::string mesh_error_of(const std::string& bytes) {
  std::vector<std::array<uint32_t, 3>> triangles;
  try {
    dg::host::parse_ply_mesh(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), "in.ply", triangles);
  } catch (const dg::host::PointFileError& e) {
    return e.what();
  }
  return "";
}

const char* kSquareHeader =
    "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 2\nproperty list uchar int vertex_indices\nend_header\n";

}  // namespace

TEST(PlyReader, AMeshsFacesBecomeTrianglesAQuadAFan) {
  // A quad and a triangle; vertex 4 repeats vertex 0, which a mesh may do.
  const std::string text = std::string(kSquareHeader) + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 0\n4 0 1 2 3\n3 1 4 2\n";
  std::vector<std::array<uint32_t, 3>> triangles;
  const dg::host::PointCloud c =
      dg::host::parse_ply_mesh(reinterpret_cast<const uint8_t*>(text.data()), text.size(), "in.ply", triangles);
  LONGS_EQUAL(5, c.points.size());
  LONGS_EQUAL(3, triangles.size());
  LONGS_EQUAL(0, triangles[1][0]);
  LONGS_EQUAL(2, triangles[1][1]);
  LONGS_EQUAL(3, triangles[1][2]);
  // Read as points, the repeated vertex is the error it always was.
  STRCMP_CONTAINS("in.ply", error_of(text).c_str());
}

TEST(PlyReader, AMeshsBadFaceIsNamed) {
  STRCMP_CONTAINS("face 2: vertex index 7 is not one of the 5 vertices",
                  mesh_error_of(std::string(kSquareHeader) + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 2 0\n3 0 1 2\n3 0 1 7\n").c_str());
  STRCMP_CONTAINS("face 1 has fewer than three corners",
                  mesh_error_of(std::string(kSquareHeader) + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 2 0\n2 0 1\n3 0 1 2\n").c_str());
  STRCMP_CONTAINS("a PLY nominal must be a mesh",
                  mesh_error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                                "end_header\n0 0 0\n").c_str());
}

namespace {

// `count` vertices (double x, y, z, uint line, float sigma, uchar red), as binary in either byte
// order or as ASCII; `edit` may change vertex values before they are written.
struct PlyVertex {
  double x, y, z;
  uint32_t line;
  float sigma;
};

std::vector<PlyVertex> many_vertices(size_t count) {
  std::vector<PlyVertex> v(count);
  for (size_t i = 0; i < count; ++i) {
    v[i] = {0.37 * static_cast<double>(i % 173), 0.11 * static_cast<double>(i / 173), std::sin(0.001 * static_cast<double>(i)),
            static_cast<uint32_t>(i / 173), 0.001f + 0.0001f * static_cast<float>(i % 7)};
  }
  return v;
}

std::string many_vertices_ply(const std::vector<PlyVertex>& v, const char* format) {
  std::string s = std::string("ply\nformat ") + format + " 1.0\nelement vertex " + std::to_string(v.size()) +
                  "\nproperty double x\nproperty double y\nproperty double z\nproperty uint line\nproperty float sigma\n"
                  "property uchar red\nend_header\n";
  const bool ascii = std::strcmp(format, "ascii") == 0, big = std::strcmp(format, "binary_big_endian") == 0;
  for (const PlyVertex& p : v) {
    if (ascii) {
      char row[160];
      std::snprintf(row, sizeof row, "%.17g %.17g %.17g %u %.17g 7\n", p.x, p.y, p.z, p.line, static_cast<double>(p.sigma));
      s += row;
      continue;
    }
    put<double>(s, p.x, big);
    put<double>(s, p.y, big);
    put<double>(s, p.z, big);
    put<uint32_t>(s, p.line, big);
    put<float>(s, p.sigma, big);
    put<uint8_t>(s, 7, big);
  }
  return s;
}

}  // namespace

// Binary vertices of one record size are decoded on every core at once, the others value by value:
// both byte orders read what the ASCII file of the same vertices holds.
TEST(PlyReader, ManyBinaryVerticesReadAsTheirAsciiTwin) {
  const std::vector<PlyVertex> v = many_vertices(20000);
  const dg::host::PointCloud ascii = read(many_vertices_ply(v, "ascii"));
  for (const char* format : {"binary_little_endian", "binary_big_endian"}) {
    const dg::host::PointCloud c = read(many_vertices_ply(v, format));
    LONGS_EQUAL(v.size(), c.points.size());
    CHECK(c.line.has_value() && c.sigma.has_value());
    for (size_t i = 0; i < v.size(); ++i) {
      DOUBLES_EQUAL(ascii.points[i].x, c.points[i].x, 0);
      DOUBLES_EQUAL(ascii.points[i].y, c.points[i].y, 0);
      DOUBLES_EQUAL(ascii.points[i].z, c.points[i].z, 0);
      LONGS_EQUAL((*ascii.line)[i], (*c.line)[i]);
      DOUBLES_EQUAL((*ascii.sigma)[i], (*c.sigma)[i], 0);
    }
  }
}

// A bad value among many binary vertices is named by the first vertex that holds one, as when the
// file is read value by value.
TEST(PlyReader, ABadValueAmongManyBinaryVerticesNamesTheFirstVertexHoldingOne) {
  std::vector<PlyVertex> v = many_vertices(20000);
  v[17000].z = std::nan("");
  v[12345].y = HUGE_VAL;
  STRCMP_CONTAINS("in.ply: vertex 12345: 'y' is not finite", error_of(many_vertices_ply(v, "binary_little_endian")).c_str());
  v = many_vertices(20000);
  v[15001].sigma = 0;
  STRCMP_CONTAINS("in.ply: vertex 15001: sigma must be from 0.000001 to 1000000 mm", error_of(many_vertices_ply(v, "binary_big_endian")).c_str());
  v = many_vertices(20000);
  v[18000].x = -3e6;
  STRCMP_CONTAINS("in.ply: vertex 18000: 'x': coordinates and normals must lie within +-1000000 mm (1 km)",
                  error_of(many_vertices_ply(v, "binary_little_endian")).c_str());
  v = many_vertices(20000);
  v[9000] = v[3];
  STRCMP_CONTAINS("in.ply: vertex 9000: the same point as in.ply: vertex 3", error_of(many_vertices_ply(v, "binary_little_endian")).c_str());
  std::string cut = many_vertices_ply(many_vertices(20000), "binary_little_endian");
  cut.resize(cut.size() - 40);  // the last vertex (33 bytes) and part of the one before
  STRCMP_CONTAINS("in.ply: file ends inside vertex 19998", error_of(cut).c_str());
}
