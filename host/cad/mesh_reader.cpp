// STL and OBJ meshes read as nominals: binary or ASCII STL with its corners welded, OBJ faces as fans.
#include "host/cad/mesh_reader.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <vector>

#include "host/cad/vertex_welder.h"
#include "host/io/file_name.h"
#include "host/io/whole_file.h"

namespace dg::host {

namespace {

void check_finite(const Point3& p, const std::string& where) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
    throw MeshFileError(where + ": a coordinate is not a finite number");
  }
}

float little_endian_float(const uint8_t* at) {
  const uint32_t bits = static_cast<uint32_t>(at[0]) | static_cast<uint32_t>(at[1]) << 8 | static_cast<uint32_t>(at[2]) << 16 |
                        static_cast<uint32_t>(at[3]) << 24;
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// A triangle whose corners weld into fewer than three vertices has no area: it is left out (STL
// exporters write such slivers), and the mesh's count says how many were.
void add_triangle(Mesh& mesh, uint32_t a, uint32_t b, uint32_t c) {
  if (a == b || b == c || c == a) return;
  mesh.triangles.push_back({a, b, c});
}

Mesh parse_binary_stl(const uint8_t* data, size_t count, const std::string& name) {
  Mesh mesh;
  VertexWelder welder(mesh);
  for (size_t t = 0; t < count; ++t) {
    const uint8_t* record = data + 84 + 50 * t;
    uint32_t corner[3];
    for (int k = 0; k < 3; ++k) {
      const uint8_t* at = record + 12 + 12 * k;
      const Point3 p{little_endian_float(at), little_endian_float(at + 4), little_endian_float(at + 8)};
      check_finite(p, name + ": triangle " + std::to_string(t + 1));
      corner[k] = welder.add(p);
    }
    add_triangle(mesh, corner[0], corner[1], corner[2]);
  }
  return mesh;
}

Mesh parse_ascii_stl(const std::string& text, const std::string& name) {
  Mesh mesh;
  VertexWelder welder(mesh);
  std::istringstream lines(text);
  std::string line;
  size_t line_number = 0;
  uint32_t corner[3];
  int corners = 0;
  while (std::getline(lines, line)) {
    ++line_number;
    std::istringstream words(line);
    std::string word;
    if (!(words >> word)) continue;
    const std::string where = name + ": line " + std::to_string(line_number);
    if (word == "vertex") {
      std::string x, y, z, rest;
      if (!(words >> x >> y >> z) || (words >> rest)) throw MeshFileError(where + ": `vertex` needs three numbers");
      Point3 p;
      double* out[3] = {&p.x, &p.y, &p.z};
      const std::string* in[3] = {&x, &y, &z};
      for (int k = 0; k < 3; ++k) {
        char* end = nullptr;
        errno = 0;
        *out[k] = std::strtod(in[k]->c_str(), &end);
        if (end == in[k]->c_str() || *end != '\0') throw MeshFileError(where + ": `" + *in[k] + "` is not a number");
      }
      check_finite(p, where);
      if (corners == 3) throw MeshFileError(where + ": a fourth vertex in one facet");
      corner[corners++] = welder.add(p);
    } else if (word == "endloop") {
      if (corners != 3) throw MeshFileError(where + ": a facet with " + std::to_string(corners) + " vertices, not 3");
      add_triangle(mesh, corner[0], corner[1], corner[2]);
      corners = 0;
    } else if (word == "solid" || word == "facet" || word == "outer" || word == "endfacet" || word == "endsolid") {
    } else {
      throw MeshFileError(where + ": `" + word + "` is not an STL keyword");
    }
  }
  if (corners != 0) throw MeshFileError(name + ": the file ends inside a facet");
  return mesh;
}

void require_triangles(const Mesh& mesh, const std::string& name) {
  if (mesh.triangles.empty()) throw MeshFileError(name + ": the mesh holds no triangles with area");
}

}  // namespace

Mesh parse_stl(const uint8_t* data, size_t size, const std::string& name) {
  if (size >= 84) {
    const size_t count = static_cast<size_t>(data[80]) | static_cast<size_t>(data[81]) << 8 | static_cast<size_t>(data[82]) << 16 |
                         static_cast<size_t>(data[83]) << 24;
    if (count <= (size - 84) / 50 && 84 + 50 * count == size) {
      Mesh mesh = parse_binary_stl(data, count, name);
      require_triangles(mesh, name);
      return mesh;
    }
  }
  const std::string text(reinterpret_cast<const char*>(data), size);
  const size_t start = text.find_first_not_of(" \t\r\n");
  if (start == std::string::npos || text.compare(start, 5, "solid") != 0) {
    throw MeshFileError(name + ": neither a binary STL (its size, " + std::to_string(size) +
                        " bytes, does not match its triangle count) nor an ASCII one (it does not begin with `solid`)");
  }
  Mesh mesh = parse_ascii_stl(text, name);
  require_triangles(mesh, name);
  return mesh;
}

Mesh parse_obj(const std::string& text, const std::string& name) {
  Mesh mesh;
  std::istringstream lines(text);
  std::string line;
  size_t line_number = 0;
  std::vector<std::pair<uint32_t, size_t>> faces_to_check;
  while (std::getline(lines, line)) {
    ++line_number;
    std::istringstream words(line);
    std::string word;
    if (!(words >> word) || word[0] == '#') continue;
    const std::string where = name + ": line " + std::to_string(line_number);
    if (word == "v") {
      std::string value;
      double xyz[3];
      for (double& c : xyz) {
        if (!(words >> value)) throw MeshFileError(where + ": `v` needs three numbers");
        char* end = nullptr;
        c = std::strtod(value.c_str(), &end);
        if (end == value.c_str() || *end != '\0') throw MeshFileError(where + ": `" + value + "` is not a number");
      }
      const Point3 p{xyz[0], xyz[1], xyz[2]};
      check_finite(p, where);
      mesh.vertices.push_back(p);
    } else if (word == "f") {
      std::vector<uint32_t> corners;
      std::string corner;
      while (words >> corner) {
        const std::string index_text = corner.substr(0, corner.find('/'));
        char* end = nullptr;
        errno = 0;
        const long index = std::strtol(index_text.c_str(), &end, 10);
        if (end == index_text.c_str() || *end != '\0' || errno == ERANGE || index == 0) {
          throw MeshFileError(where + ": `" + corner + "` is not a vertex index (1-based, or negative from the last)");
        }
        // Negative indices count back from the vertices read so far.
        const long count = static_cast<long>(mesh.vertices.size());
        const long zero_based = index > 0 ? index - 1 : count + index;
        if (zero_based < 0 || zero_based >= count) {
          throw MeshFileError(where + ": vertex " + std::to_string(index) + " is not among the " + std::to_string(count) +
                              " vertices defined before it");
        }
        corners.push_back(static_cast<uint32_t>(zero_based));
      }
      if (corners.size() < 3) throw MeshFileError(where + ": a face needs at least three corners");
      for (size_t k = 1; k + 1 < corners.size(); ++k) add_triangle(mesh, corners[0], corners[k], corners[k + 1]);
    } else if (word == "vt" || word == "vn" || word == "vp" || word == "g" || word == "o" || word == "s" ||
               word == "usemtl" || word == "mtllib" || word == "l") {
    } else {
      throw MeshFileError(where + ": `" + word + "` is not an OBJ statement this reader knows");
    }
  }
  require_triangles(mesh, name);
  return mesh;
}

Mesh read_mesh(const std::string& path) {
  std::string bytes;
  if (!read_whole_file(path, &bytes)) throw MeshFileError(path + ": cannot be read: " + std::strerror(errno));
  switch (file_format(path)) {
    case FileFormat::kStl: return parse_stl(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), path);
    case FileFormat::kObj: return parse_obj(bytes, path);
    default: throw MeshFileError(path + ": a mesh nominal must be .stl or .obj");
  }
}

}  // namespace dg::host
