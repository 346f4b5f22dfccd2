// A strict IGES reader for entity 128: sections by column 73, free-format parameters, Hollerith
// strings, D exponents.
#include "host/cad/iges_reader.h"
#include "host/io/whole_file.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <vector>

namespace dg::host {
namespace {

struct Line {
  std::string data;  // columns 1-72
  size_t number;     // line in the file, for messages
};

struct Sections {
  std::vector<Line> start, global, directory, parameter;
};

Sections split_sections(const std::string& text, const std::string& name) {
  Sections s;
  std::istringstream in(text);
  std::string row;
  size_t number = 0;
  while (std::getline(in, row)) {
    ++number;
    if (!row.empty() && row.back() == '\r') row.pop_back();
    if (row.empty()) continue;
    if (row.size() < 73 || row.size() > 80) {
      throw IgesError(name + ":" + std::to_string(number) + ": not an IGES line (" + std::to_string(row.size()) +
                      " columns, the fixed layout has 80)");
    }
    const Line line{row.substr(0, 72), number};
    switch (row[72]) {
      case 'S': s.start.push_back(line); break;
      case 'G': s.global.push_back(line); break;
      case 'D': s.directory.push_back(line); break;
      case 'P': s.parameter.push_back(line); break;
      case 'T': break;
      case 'B':
      case 'C': throw IgesError(name + ":" + std::to_string(number) + ": binary or compressed IGES is not supported");
      default: throw IgesError(name + ":" + std::to_string(number) + ": unknown section letter '" + std::string(1, row[72]) + "'");
    }
  }
  if (s.global.empty() || s.directory.empty() || s.parameter.empty()) {
    throw IgesError(name + ": not an IGES file (no global, directory or parameter section)");
  }
  return s;
}

// Free-format parameters: tokens separated by `delimiter`, ended by `record`; nH strings kept whole.
std::vector<std::string> tokens(const std::string& text, char delimiter, char record, const std::string& where) {
  std::vector<std::string> out;
  std::string current;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == record) {
      out.push_back(current);
      return out;
    }
    if (c == delimiter) {
      out.push_back(current);
      current.clear();
      continue;
    }
    if (c == 'H' && !current.empty() && current.find_first_not_of(" 0123456789") == std::string::npos) {
      const long n = std::strtol(current.c_str(), nullptr, 10);
      if (n < 0 || static_cast<size_t>(n) > text.size() - i - 1) throw IgesError(where + ": a string runs past the end");
      current = text.substr(i + 1, static_cast<size_t>(n));
      i += static_cast<size_t>(n);
      continue;
    }
    current += c;
  }
  throw IgesError(where + ": parameters end without the record delimiter '" + std::string(1, record) + "'");
}

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(' ');
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(' ') - a + 1);
}

double real(const std::string& token, const std::string& where, const char* what) {
  std::string t = trim(token);
  for (char& c : t) {
    if (c == 'D' || c == 'd') c = 'E';
  }
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (t.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v)) {
    throw IgesError(where + ": " + what + " is not a finite number: '" + trim(token) + "'");
  }
  return v;
}

long integer(const std::string& token, const std::string& where, const char* what) {
  const double v = real(token, where, what);
  if (v != std::floor(v) || std::fabs(v) > 1e9) throw IgesError(where + ": " + what + " is not an integer: '" + trim(token) + "'");
  return static_cast<long>(v);
}

// Millimetres per model unit from the global section (parameters 13, 14, 15).
double mm_per_unit(const std::vector<std::string>& g, const std::string& where) {
  const double scale = g.size() > 12 && !trim(g[12]).empty() ? real(g[12], where, "model space scale") : 1.0;
  const long flag = g.size() > 13 && !trim(g[13]).empty() ? integer(g[13], where, "units flag") : 1;
  static const double kMm[] = {0, 25.4, 1.0, 0, 304.8, 1609344.0, 1000.0, 1e6, 0.0254, 0.001, 10.0, 2.54e-5};
  if (flag < 1 || flag > 11 || flag == 3) {
    throw IgesError(where + ": units flag " + std::to_string(flag) + " is not one this reader knows (1, 2, 4-11)");
  }
  if (!(scale > 0)) throw IgesError(where + ": model space scale must be positive");
  return kMm[flag] / scale;
}

}  // namespace

BSplineSurface parse_iges_surface(const std::string& text, const std::string& name) {
  const Sections s = split_sections(text, name);
  std::string global;
  for (const Line& l : s.global) global += l.data;
  char delimiter = ',', record = ';';
  // The first two global parameters may redefine the delimiters (as 1Hx); each defaults when empty.
  size_t second = 1;  // where the second parameter starts when the first is empty
  if (global.size() >= 4 && global.compare(0, 2, "1H") == 0) {
    delimiter = global[2];
    second = 4;
  }
  if (global.size() >= second + 3 && global.compare(second, 2, "1H") == 0) record = global[second + 2];
  const std::string g_where = name + ":" + std::to_string(s.global.front().number);
  const std::vector<std::string> g = tokens(global, delimiter, record, g_where + " (global section)");
  const double to_mm = mm_per_unit(g, g_where);

  if (s.directory.size() % 2 != 0) throw IgesError(name + ": the directory section has an odd number of lines");
  // One untrimmed surface is what this reader returns: a file of trimmed or several surfaces would
  // be measured against the wrong shape, so it is refused instead.
  int surfaces = 0;
  for (size_t d = 0; d < s.directory.size(); d += 2) {
    const std::string where = name + ":" + std::to_string(s.directory[d].number);
    const long type = integer(s.directory[d].data.substr(0, 8), where, "entity type");
    if (type == 143 || type == 144) {
      throw IgesError(where + ": a trimmed surface (entity " + std::to_string(type) +
                      ") is not read here; inspect against the SURF.json the faces were exported from");
    }
    if (type == 128 && ++surfaces > 1) {
      throw IgesError(where + ": the file holds more than one surface (entity 128); one untrimmed surface is read");
    }
  }
  for (size_t d = 0; d < s.directory.size(); d += 2) {
    const Line& first = s.directory[d];
    const std::string where = name + ":" + std::to_string(first.number);
    if (integer(first.data.substr(0, 8), where, "entity type") != 128) continue;
    const long pointer = integer(first.data.substr(8, 8), where, "parameter pointer");
    const long count = integer(s.directory[d + 1].data.substr(24, 8), where, "parameter line count");
    if (pointer < 1 || count < 1 || static_cast<size_t>(pointer - 1 + count) > s.parameter.size()) {
      throw IgesError(where + ": entity 128's parameters (lines " + std::to_string(pointer) + ", " + std::to_string(count) +
                      " of them) lie outside the parameter section");
    }
    std::string data;
    for (long k = 0; k < count; ++k) data += s.parameter[static_cast<size_t>(pointer - 1 + k)].data.substr(0, 64);
    const std::string p_where = name + ":" + std::to_string(s.parameter[static_cast<size_t>(pointer - 1)].number);
    const std::vector<std::string> p = tokens(data, delimiter, record, p_where);
    if (p.size() < 10 || integer(p[0], p_where, "entity type") != 128) throw IgesError(p_where + ": not an entity 128 record");
    const long k1 = integer(p[1], p_where, "K1"), k2 = integer(p[2], p_where, "K2");
    const long m1 = integer(p[3], p_where, "M1"), m2 = integer(p[4], p_where, "M2");
    if (m1 < 1 || m2 < 1 || m1 > 7 || m2 > 7 || k1 < m1 || k2 < m2 || k1 > 100000 || k2 > 100000 || (k1 + 1) * (k2 + 1) > 10000000) {
      throw IgesError(p_where + ": degrees " + std::to_string(m1) + " x " + std::to_string(m2) + " with upper indices " +
                      std::to_string(k1) + " x " + std::to_string(k2) + " are not a surface this reader takes (degree 1..7)");
    }
    const size_t nu = static_cast<size_t>(k1 + 1), nv = static_cast<size_t>(k2 + 1);
    const size_t knots_u = nu + static_cast<size_t>(m1) + 1, knots_v = nv + static_cast<size_t>(m2) + 1;
    const size_t needed = 10 + knots_u + knots_v + nu * nv * 4 + 4;
    if (p.size() < needed) {
      throw IgesError(p_where + ": entity 128 has " + std::to_string(p.size()) + " parameters, its counts need " + std::to_string(needed));
    }
    BSplineSurface out;
    out.degree_u = static_cast<int>(m1);
    out.degree_v = static_cast<int>(m2);
    out.count_u = static_cast<int>(nu);
    out.count_v = static_cast<int>(nv);
    size_t at = 10;
    for (size_t k = 0; k < knots_u; ++k) out.knots_u.push_back(real(p[at++], p_where, "a knot"));
    for (size_t k = 0; k < knots_v; ++k) out.knots_v.push_back(real(p[at++], p_where, "a knot"));
    const double w0 = real(p[at], p_where, "a weight");
    for (size_t k = 0; k < nu * nv; ++k) {
      const double w = real(p[at++], p_where, "a weight");
      if (!(w > 0)) throw IgesError(p_where + ": weights must be positive");
      if (std::fabs(w - w0) > 1e-12 * w0) throw IgesError(p_where + ": a rational surface (unequal weights) is not supported");
    }
    out.control.resize(nu * nv);
    for (size_t j = 0; j < nv; ++j)
      for (size_t i = 0; i < nu; ++i) {
        Point3 c;
        c.x = real(p[at++], p_where, "a control point") * to_mm;
        c.y = real(p[at++], p_where, "a control point") * to_mm;
        c.z = real(p[at++], p_where, "a control point") * to_mm;
        out.at(static_cast<int>(i), static_cast<int>(j)) = c;
      }
    std::string why;
    if (!is_valid(out, &why)) throw IgesError(p_where + ": entity 128 is not a valid surface: " + why);
    return out;
  }
  throw IgesError(name + ": no B-spline surface (entity 128) in the file");
}

BSplineSurface read_iges_surface(const std::string& path) {
  std::string text;
  if (!read_whole_file(path, &text)) throw IgesError(path + ": cannot open: " + std::strerror(errno));
  return parse_iges_surface(text, path);
}

}  // namespace dg::host
