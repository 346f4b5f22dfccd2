// PLY point clouds (ASCII and binary, either byte order): the vertex element's x, y, z and optional
// normals, with every other element skipped so meshes from scanners and CAD programs read too.
#include "host/scan/ply_reader.h"

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "host/io/text_field.h"
#include "host/parallel/parallel_for.h"

namespace dg::host {
namespace {

enum class PlyFormat { kAscii, kBinaryLittle, kBinaryBig };

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

// Vertex properties we read, and those we know to be appearance data that a fit ignores. Anything
// else is an error, as an unknown CSV column is: a property we do not understand may matter.
// `line` and `sigma` are ours: the PLY that `digitizer export` writes carries the scan line.
constexpr int kSlots = 8;
const char* const kUsed[kSlots] = {"x", "y", "z", "nx", "ny", "nz", "line", "sigma"};
// kUsed[0] to kUsed[kCoordinateSlots - 1] are coordinates and normals, bounded by plausible_coordinate.
constexpr int kCoordinateSlots = 6;
const char* const kIgnored[] = {"red", "green", "blue", "alpha", "diffuse_red", "diffuse_green", "diffuse_blue",
                                "intensity", "confidence", "quality", "scalar_intensity", "s", "t", "u", "v"};

bool one_of(const std::string& s, const char* const* list, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    if (s == list[i]) return true;
  }
  return false;
}

bool parse_type(const std::string& word, PlyType& type) {
  static const struct {
    const char* name;
    PlyType type;
  } kTypes[] = {{"char", PlyType::kInt8},     {"int8", PlyType::kInt8},       {"uchar", PlyType::kUint8},
                {"uint8", PlyType::kUint8},   {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
                {"ushort", PlyType::kUint16}, {"uint16", PlyType::kUint16},   {"int", PlyType::kInt32},
                {"int32", PlyType::kInt32},   {"uint", PlyType::kUint32},     {"uint32", PlyType::kUint32},
                {"float", PlyType::kFloat32}, {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
                {"float64", PlyType::kFloat64}};
  for (const auto& t : kTypes) {
    if (word == t.name) {
      type = t.type;
      return true;
    }
  }
  return false;
}

size_t type_size(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUint8: return 1;
    case PlyType::kInt16:
    case PlyType::kUint16: return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32: return 4;
    case PlyType::kFloat64: return 8;
  }
  return 1;
}

// One binary value of type `t` at `at` (type_size(t) bytes), as a double.
double decode(PlyType t, const uint8_t* at, bool big_endian) {
  const size_t n = type_size(t);
  // The value's bytes, least significant first; the shifts below then compile to plain loads.
  uint8_t b[8];
  if (big_endian) {
    for (size_t i = 0; i < n; ++i) b[i] = at[n - 1 - i];
  } else {
    std::memcpy(b, at, n);
  }
  switch (t) {
    case PlyType::kInt8: return static_cast<int8_t>(b[0]);
    case PlyType::kUint8: return b[0];
    case PlyType::kInt16: return static_cast<int16_t>(b[0] | b[1] << 8);
    case PlyType::kUint16: return static_cast<uint16_t>(b[0] | b[1] << 8);
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32: {
      const uint32_t u = static_cast<uint32_t>(b[0]) | static_cast<uint32_t>(b[1]) << 8 |
                         static_cast<uint32_t>(b[2]) << 16 | static_cast<uint32_t>(b[3]) << 24;
      if (t == PlyType::kUint32) return u;
      if (t == PlyType::kInt32) return static_cast<int32_t>(u);
      float f;
      std::memcpy(&f, &u, sizeof f);
      return f;
    }
    case PlyType::kFloat64: {
      uint64_t u = 0;
      for (int i = 0; i < 8; ++i) u |= static_cast<uint64_t>(b[i]) << (8 * i);
      double d;
      std::memcpy(&d, &u, sizeof d);
      return d;
    }
  }
  return 0;
}

// Reads binary values from the body with bounds checks; `where` names the vertex being read.
class BinaryCursor {
 public:
  BinaryCursor(const uint8_t* data, size_t size, bool big_endian) : data_(data), size_(size), big_(big_endian) {}
  size_t left() const { return size_ - offset_; }

  // `where()` names the element for a message; it is called only when there is one to give.
  template <typename Where>
  double read(PlyType t, const std::string& name, const Where& where) {
    const size_t n = type_size(t);
    if (size_ - offset_ < n) throw PointFileError(name + ": file ends inside " + where());
    const double value = decode(t, data_ + offset_, big_);
    offset_ += n;
    return value;
  }
  // Past `n` bytes the caller has read by itself (at most left()).
  void skip(size_t n) { offset_ += n; }
  size_t offset() const { return offset_; }
  size_t size() const { return size_; }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t offset_ = 0;
  bool big_;
};

// Reads ASCII body values token by token, tracking the text line for messages.
class AsciiCursor {
 public:
  AsciiCursor(const char* text, size_t size, size_t first_line) : p_(text), end_(text + size), line_(first_line) {}
  // After the last element: anything but white space is a row the header does not count.
  bool at_end() {
    while (p_ < end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\r' || *p_ == '\n')) {
      if (*p_ == '\n') ++line_;
      ++p_;
    }
    return p_ == end_;
  }

  double read(const std::string& name, const std::string& property) {
    while (p_ < end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\r' || *p_ == '\n')) {
      if (*p_ == '\n') ++line_;
      ++p_;
    }
    const char* start = p_;
    while (p_ < end_ && !(*p_ == ' ' || *p_ == '\t' || *p_ == '\r' || *p_ == '\n')) ++p_;
    const std::string token(start, p_);
    // At the end of the file, name the line of the last value: that is the short row.
    if (token.empty()) throw PointFileError(name + ":" + std::to_string(last_line_) + ": file ends before '" + property + "'");
    last_line_ = line_;
    double v = 0;
    if (!parse_decimal(token, &v)) {
      throw PointFileError(name + ":" + std::to_string(line_) + ": " + quoted(property) +
                           " is not a finite decimal number: " + quoted(token));
    }
    return v;
  }
  size_t line() const { return line_; }

 private:
  const char* p_;
  const char* end_;
  size_t line_;
  size_t last_line_ = line_;
};

struct Header {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  size_t body_offset = 0;
  size_t body_line = 0;  // text line where the body starts (ASCII)
};

Header parse_header(const uint8_t* data, size_t size, const std::string& name) {
  Header h;
  size_t pos = 0, line_no = 0;
  bool have_format = false;
  auto next_line = [&](std::string& out) {
    if (pos >= size) return false;
    const void* nl = std::memchr(data + pos, '\n', size - pos);
    const size_t end = nl ? static_cast<size_t>(static_cast<const uint8_t*>(nl) - data) : size;
    out.assign(reinterpret_cast<const char*>(data) + pos, end - pos);
    if (!out.empty() && out.back() == '\r') out.pop_back();
    pos = nl ? end + 1 : size;
    ++line_no;
    return true;
  };
  std::string row;
  if (!next_line(row) || row != "ply") throw PointFileError(name + ":1: not a PLY file (no 'ply' magic line)");
  while (true) {
    if (!next_line(row)) throw PointFileError(name + ": header has no end_header");
    const std::string here = name + ":" + std::to_string(line_no) + ": ";
    std::istringstream words(row);
    std::string key;
    words >> key;
    if (key.empty() || key == "comment" || key == "obj_info") continue;
    if (key == "end_header") break;
    if (key == "format") {
      std::string kind, version;
      words >> kind >> version;
      if (kind == "ascii") h.format = PlyFormat::kAscii;
      else if (kind == "binary_little_endian") h.format = PlyFormat::kBinaryLittle;
      else if (kind == "binary_big_endian") h.format = PlyFormat::kBinaryBig;
      else throw PointFileError(here + "unknown PLY format '" + kind + "'");
      if (version != "1.0") throw PointFileError(here + "PLY version '" + version + "' (only 1.0 exists)");
      have_format = true;
    } else if (key == "element") {
      PlyElement e;
      std::string count;
      words >> e.name >> count;
      char* used = nullptr;
      const unsigned long long n = std::strtoull(count.c_str(), &used, 10);
      if (e.name.empty() || count.empty() || *used != '\0' || count[0] == '-') {
        throw PointFileError(here + "element needs a name and a count");
      }
      e.count = n;
      for (const PlyElement& earlier : h.elements) {
        if (earlier.name == e.name) throw PointFileError(here + "element '" + e.name + "' appears twice");
      }
      h.elements.push_back(e);
    } else if (key == "property") {
      if (h.elements.empty()) throw PointFileError(here + "property before any element");
      PlyProperty p;
      std::string type;
      words >> type;
      if (type == "list") {
        std::string count_type, item_type;
        words >> count_type >> item_type >> p.name;
        if (!parse_type(count_type, p.count_type) || !parse_type(item_type, p.type)) {
          throw PointFileError(here + "unknown list type '" + count_type + " " + item_type + "'");
        }
        p.is_list = true;
      } else {
        words >> p.name;
        if (!parse_type(type, p.type)) throw PointFileError(here + "unknown property type '" + type + "'");
      }
      if (p.name.empty()) throw PointFileError(here + "property has no name");
      h.elements.back().properties.push_back(p);
    } else {
      throw PointFileError(here + "unknown header keyword '" + key + "'");
    }
  }
  if (!have_format) throw PointFileError(name + ": header has no format line");
  h.body_offset = pos;
  h.body_line = line_no + 1;
  return h;
}

}  // namespace

namespace {

// A binary vertex element of scalars only has records of one size, so each vertex's values lie at
// a known offset and the vertices are decoded on every core (one value at a time through the
// cursor, a million took 0.035 s, a third of reading the file). `body` holds at least
// vertex.count records. False when a value is one the reading refuses (not finite, a bad line or
// sigma): the caller then reads value by value, which names the first such vertex.
bool read_fixed_vertices(const uint8_t* body, const PlyElement& vertex, const int (&slot_of)[kSlots], bool big_endian,
                         PointCloud& cloud) {
  size_t stride = 0;
  std::vector<size_t> offset_of;
  for (const PlyProperty& p : vertex.properties) {
    offset_of.push_back(stride);
    stride += type_size(p.type);
  }
  const size_t count = static_cast<size_t>(vertex.count);
  cloud.points.resize(count);
  if (cloud.normal) cloud.normal->resize(count);
  if (cloud.line) cloud.line->resize(count);
  if (cloud.sigma) cloud.sigma->resize(count);
  std::atomic<bool> refused{false};
  parallel_for(count, [&](size_t begin, size_t end, unsigned) {
    for (size_t i = begin; i < end; ++i) {
      const uint8_t* record = body + i * stride;
      double values[kSlots] = {};
      bool ok = true;
      for (int s = 0; s < kSlots; ++s) {
        if (slot_of[s] < 0) continue;
        const size_t k = static_cast<size_t>(slot_of[s]);
        values[s] = decode(vertex.properties[k].type, record + offset_of[k], big_endian);
        ok = ok && std::isfinite(values[s]) && (s >= kCoordinateSlots || plausible_coordinate(values[s]));
      }
      cloud.points[i] = {values[0], values[1], values[2]};
      if (cloud.normal) (*cloud.normal)[i] = {values[3], values[4], values[5]};
      if (cloud.line) {
        uint32_t l = 0;
        ok = ok && line_number_of(values[6], l);
        (*cloud.line)[i] = l;
      }
      if (cloud.sigma) {
        ok = ok && valid_sigma(values[7]);
        (*cloud.sigma)[i] = values[7];
      }
      if (!ok) refused.store(true, std::memory_order_relaxed);
    }
  }, 4096);
  return !refused.load();
}

PointCloud parse_ply(const uint8_t* data, size_t size, const std::string& name, std::vector<std::array<uint32_t, 3>>* triangles) {
  const Header h = parse_header(data, size, name);
  size_t vertex_index = h.elements.size();
  for (size_t i = 0; i < h.elements.size(); ++i) {
    if (h.elements[i].name == "vertex") {
      vertex_index = i;
      break;
    }
  }
  if (vertex_index == h.elements.size()) throw PointFileError(name + ": no 'vertex' element");
  const PlyElement& vertex = h.elements[vertex_index];
  int slot_of[kSlots] = {-1, -1, -1, -1, -1, -1, -1, -1};  // kUsed[s] -> property index
  for (size_t k = 0; k < vertex.properties.size(); ++k) {
    const PlyProperty& p = vertex.properties[k];
    bool used = false;
    for (int s = 0; s < kSlots; ++s) {
      if (p.name == kUsed[s]) {
        if (slot_of[s] >= 0) throw PointFileError(name + ": vertex property '" + p.name + "' appears twice");
        if (p.is_list) throw PointFileError(name + ": vertex property '" + p.name + "' is a list");
        slot_of[s] = static_cast<int>(k);
        used = true;
      }
    }
    // CloudCompare names its scalar fields scalar_NAME (a deviation, a classification): data about
    // the points, not where they are, so they are read past like colours.
    const bool scalar_field = p.name.rfind("scalar_", 0) == 0 && !p.is_list;
    if (!used && !scalar_field && !one_of(p.name, kIgnored, sizeof kIgnored / sizeof kIgnored[0])) {
      throw PointFileError(name + ": unknown vertex property '" + p.name +
                           "' (read: x,y,z,nx,ny,nz,line,sigma; colours, intensity and scalar_ fields are ignored)");
    }
  }
  for (int s = 0; s < 3; ++s) {
    if (slot_of[s] < 0) throw PointFileError(name + ": vertex element has no '" + kUsed[s] + "' property");
  }
  const int normals = (slot_of[3] >= 0) + (slot_of[4] >= 0) + (slot_of[5] >= 0);
  if (normals != 0 && normals != 3) throw PointFileError(name + ": normals need all of nx, ny, nz");
  // A count larger than the bytes could hold is a damaged header, not a reason to reserve gigabytes.
  const size_t body = size - h.body_offset;
  if (vertex.count > body) throw PointFileError(name + ": header promises " + std::to_string(vertex.count) + " vertices, the file is too short");

  PointCloud cloud;
  if (normals == 3) cloud.normal.emplace();
  if (slot_of[6] >= 0) cloud.line.emplace();
  if (slot_of[7] >= 0) cloud.sigma.emplace();
  cloud.points.reserve(static_cast<size_t>(vertex.count));
  std::vector<double> values(vertex.properties.size());
  std::vector<size_t> source;  // ASCII: each vertex's text line, for messages (binary: its number)
  const bool binary = h.format != PlyFormat::kAscii;
  BinaryCursor bin(data + h.body_offset, body, h.format == PlyFormat::kBinaryBig);
  AsciiCursor text(reinterpret_cast<const char*>(data) + h.body_offset, body, h.body_line);
  auto vertex_where = [&](uint64_t v) { return "vertex " + std::to_string(v); };
  // A mesh's faces: the element named "face" and its list of vertex indices.
  size_t face_index = h.elements.size();
  int indices_property = -1;
  for (size_t i = 0; triangles && i < h.elements.size(); ++i) {
    if (h.elements[i].name != "face") continue;
    face_index = i;
    for (size_t k = 0; k < h.elements[i].properties.size(); ++k) {
      const PlyProperty& p = h.elements[i].properties[k];
      if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) indices_property = static_cast<int>(k);
    }
  }
  if (triangles && (face_index == h.elements.size() || indices_property < 0)) {
    throw PointFileError(name + ": no 'face' element with a 'vertex_indices' list: a PLY nominal must be a mesh");
  }
  bool fixed_records = binary && vertex_index == 0;
  size_t stride = 0;
  for (const PlyProperty& p : vertex.properties) fixed_records = fixed_records && !p.is_list, stride += type_size(p.type);
  bool vertices_read = false;
  if (fixed_records && stride > 0 && body / stride >= vertex.count) {
    vertices_read = read_fixed_vertices(data + h.body_offset, vertex, slot_of, h.format == PlyFormat::kBinaryBig, cloud);
    if (!vertices_read) {
      cloud.points.clear();
      if (cloud.normal) cloud.normal->clear();
      if (cloud.line) cloud.line->clear();
      if (cloud.sigma) cloud.sigma->clear();
    }
  }
  std::vector<uint32_t> corners;
  // Every element is read (the others skipped value by value), so that what the file holds beyond
  // the header's counts is found.
  for (size_t e = 0; e < h.elements.size(); ++e) {
    const PlyElement& el = h.elements[e];
    if (e == vertex_index && vertices_read) {
      bin.skip(static_cast<size_t>(el.count) * stride);
      continue;
    }
    for (uint64_t item = 0; item < el.count; ++item) {
      // Built only for a message: a string per item was a third of reading a million vertices.
      auto where = [&] { return e == vertex_index ? vertex_where(item) : "element '" + el.name + "'"; };
      for (size_t k = 0; k < el.properties.size(); ++k) {
        const PlyProperty& p = el.properties[k];
        if (p.is_list) {
          const double n = binary ? bin.read(p.count_type, name, where) : text.read(name, p.name);
          if (!(n >= 0) || n != std::floor(n) || n > static_cast<double>(body)) {
            throw PointFileError(name + ": " + where() + ": bad list length");
          }
          const bool face_corners = e == face_index && static_cast<int>(k) == indices_property;
          corners.clear();
          for (uint64_t j = 0; j < static_cast<uint64_t>(n); ++j) {
            const double index = binary ? bin.read(p.type, name, where) : text.read(name, p.name);
            if (!face_corners) continue;
            if (!(index >= 0) || index != std::floor(index) || index >= static_cast<double>(vertex.count)) {
              char shown[32];
              std::snprintf(shown, sizeof shown, "%g", index);
              throw PointFileError(name + ": face " + std::to_string(item + 1) + ": vertex index " + shown + " is not one of the " +
                                   std::to_string(vertex.count) + " vertices (0 to " + std::to_string(vertex.count - 1) + ")");
            }
            corners.push_back(static_cast<uint32_t>(index));
          }
          if (face_corners) {
            if (corners.size() < 3) throw PointFileError(name + ": face " + std::to_string(item + 1) + " has fewer than three corners");
            for (size_t c = 1; c + 1 < corners.size(); ++c) {
              if (corners[0] != corners[c] && corners[c] != corners[c + 1] && corners[c + 1] != corners[0]) {
                triangles->push_back({corners[0], corners[c], corners[c + 1]});
              }
            }
          }
        } else {
          // Only the vertex element's values are kept: another element may have more properties
          // than `values` holds (a fuzzed face element with seven once wrote past it).
          const double value = binary ? bin.read(p.type, name, where) : text.read(name, p.name);
          if (e == vertex_index) values[k] = value;
        }
      }
      if (e != vertex_index) continue;
      auto at = [&] { return binary ? name + ": " + where() : name + ":" + std::to_string(text.line()) + " (" + where() + ")"; };
      for (int s = 0; s < kSlots; ++s) {
        if (slot_of[s] >= 0 && !std::isfinite(values[slot_of[s]])) {
          throw PointFileError(at() + ": '" + kUsed[s] + "' is not finite");
        }
        if (s < kCoordinateSlots && slot_of[s] >= 0 && !plausible_coordinate(values[slot_of[s]])) {
          throw PointFileError(at() + ": '" + kUsed[s] + "': " + kCoordinateRule);
        }
      }
      if (cloud.line) {
        uint32_t l = 0;
        if (!line_number_of(values[slot_of[6]], l)) throw PointFileError(at() + ": " + kLineNumberRule);
        cloud.line->push_back(l);
      }
      if (cloud.sigma) {
        if (!valid_sigma(values[slot_of[7]])) throw PointFileError(at() + ": " + kSigmaRule);
        cloud.sigma->push_back(values[slot_of[7]]);
      }
      cloud.points.push_back({values[slot_of[0]], values[slot_of[1]], values[slot_of[2]]});
      if (cloud.normal) cloud.normal->push_back({values[slot_of[3]], values[slot_of[4]], values[slot_of[5]]});
      if (!binary) source.push_back(text.line());
    }
  }
  if (binary ? bin.left() != 0 : !text.at_end()) {
    throw PointFileError(binary ? name + ": " + std::to_string(bin.left()) + " bytes after the elements the header counts"
                                : name + ":" + std::to_string(text.line()) + ": a row after the elements the header counts");
  }
  if (!triangles) {
    check_duplicate_points(cloud, [&](size_t i) {
      return binary ? name + ": vertex " + std::to_string(i) : name + ":" + std::to_string(source[i]);
    });
  }
  return cloud;
}

}  // namespace

PointCloud parse_ply_points(const uint8_t* data, size_t size, const std::string& name) {
  return parse_ply(data, size, name, nullptr);
}

PointCloud parse_ply_mesh(const uint8_t* data, size_t size, const std::string& name,
                          std::vector<std::array<uint32_t, 3>>& triangles) {
  triangles.clear();
  PointCloud cloud = parse_ply(data, size, name, &triangles);
  if (triangles.empty()) throw PointFileError(name + ": the mesh's faces give no triangles with three distinct corners");
  return cloud;
}

}  // namespace dg::host
