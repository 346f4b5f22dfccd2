// Mesh files in three formats, written whole and renamed into place.
#include "host/cad/mesh_writer.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "host/io/file_name.h"
#include "host/io/atomic_file.h"
#include "host/geometry/vec3.h"

namespace dg::host {
namespace {

void put_u32(std::string& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>(v >> (8 * i) & 0xFF));
}

void put_f32(std::string& out, double value) {
  const float f = static_cast<float>(value);
  uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  put_u32(out, bits);
}

}  // namespace

std::string stl_bytes(const Mesh& mesh) {
  std::string out = "bench digitizer surface mesh, binary STL, millimetres";
  out.resize(80, ' ');
  put_u32(out, static_cast<uint32_t>(mesh.triangles.size()));
  for (const auto& t : mesh.triangles) {
    const Point3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const Point3 n = cross(b - a, c - a);
    const double length = norm(n);
    const Point3 unit = length > 0 ? (1.0 / length) * n : Point3{};
    for (const Point3& p : {unit, a, b, c}) {
      put_f32(out, p.x);
      put_f32(out, p.y);
      put_f32(out, p.z);
    }
    out.push_back(0);
    out.push_back(0);
  }
  return out;
}

std::string obj_text(const Mesh& mesh) {
  std::string out = "# bench digitizer surface mesh, millimetres\n";
  char line[128];
  for (const Point3& p : mesh.vertices) {
    std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", p.x, p.y, p.z);
    out += line;
  }
  for (const auto& t : mesh.triangles) {
    std::snprintf(line, sizeof line, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
    out += line;
  }
  return out;
}

std::string ply_mesh_bytes(const Mesh& mesh) {
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment bench digitizer surface mesh, millimetres\nelement vertex " +
                    std::to_string(mesh.vertices.size()) + "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(mesh.triangles.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Point3& p : mesh.vertices) {
    put_f32(out, p.x);
    put_f32(out, p.y);
    put_f32(out, p.z);
  }
  for (const auto& t : mesh.triangles) {
    out.push_back(3);
    for (uint32_t v : t) put_u32(out, v);
  }
  return out;
}

void write_mesh(const std::string& path, const Mesh& mesh) {
  // STL and binary PLY store 32-bit floats: a vertex beyond their range would be written as
  // infinity (a surface with control points near 1e300 did that).
  for (size_t k = 0; k < mesh.vertices.size(); ++k) {
    const Point3& v = mesh.vertices[k];
    for (double c : {v.x, v.y, v.z}) {
      if (!std::isfinite(c) || std::fabs(c) > 1e30) {
        throw std::invalid_argument(path + ": mesh vertex " + std::to_string(k + 1) +
                                    " is not a finite coordinate a mesh file can hold (the surface's control points are out of range)");
      }
    }
  }
  if (!std::isfinite(mesh.chord_error_mm)) throw std::invalid_argument(path + ": the mesh's chord error is not a finite number");
  switch (file_format(path)) {
    case FileFormat::kStl: return write_file_atomically(path, stl_bytes(mesh));
    case FileFormat::kObj: return write_file_atomically(path, obj_text(mesh));
    case FileFormat::kPly: return write_file_atomically(path, ply_mesh_bytes(mesh));
    default: break;
  }
  throw std::invalid_argument(path + ": a mesh is written as .stl, .obj or .ply");
}

}  // namespace dg::host
