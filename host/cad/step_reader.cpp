// A small ISO 10303-21 reader: instances into parameter trees, then the surface and its points.
#include "host/cad/step_reader.h"
#include "host/io/whole_file.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>
#include <vector>

namespace dg::host {
namespace {

struct Value {
  enum Kind { kNumber, kString, kEnum, kRef, kList, kUnset, kTyped } kind = kUnset;
  double number = 0;
  std::string text;  // string, enumeration, or the type of a typed parameter
  long ref = 0;
  std::vector<Value> items;  // a list, or a typed parameter's arguments
};

struct Instance {
  std::string type;          // upper case; empty for a complex instance
  std::vector<Value> args;   // simple instance
  std::string raw;           // the text after '=', for complex instances
};

class Parser {
 public:
  Parser(const std::string& text, size_t pos, const std::string& where) : s_(text), p_(pos), where_(where) {}

  Value parameter(int depth) {
    if (depth > 64) fail("parameters nested too deep");
    skip();
    if (p_ >= s_.size()) fail("text ends inside parameters");
    const char c = s_[p_];
    Value v;
    if (c == '(') {
      v.kind = Value::kList;
      v.items = list(depth + 1);
    } else if (c == '\'') {
      v.kind = Value::kString;
      ++p_;
      for (;;) {
        if (p_ >= s_.size()) fail("a string does not end");
        if (s_[p_] == '\'') {
          if (p_ + 1 < s_.size() && s_[p_ + 1] == '\'') {
            v.text += '\'';
            p_ += 2;
            continue;
          }
          ++p_;
          break;
        }
        v.text += s_[p_++];
      }
    } else if (c == '.') {
      v.kind = Value::kEnum;
      const size_t end = s_.find('.', p_ + 1);
      if (end == std::string::npos) fail("an enumeration does not end");
      v.text = s_.substr(p_ + 1, end - p_ - 1);
      p_ = end + 1;
    } else if (c == '#') {
      v.kind = Value::kRef;
      ++p_;
      v.ref = integer();
    } else if (c == '$' || c == '*') {
      ++p_;
    } else if (std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+') {
      v.kind = Value::kNumber;
      const char* begin = s_.c_str() + p_;
      char* end = nullptr;
      errno = 0;
      v.number = std::strtod(begin, &end);
      if (end == begin || errno == ERANGE || !std::isfinite(v.number)) fail("a number is not a finite number");
      p_ += static_cast<size_t>(end - begin);
    } else if (std::isalpha(static_cast<unsigned char>(c))) {
      v.kind = Value::kTyped;
      v.text = keyword();
      skip();
      if (p_ >= s_.size() || s_[p_] != '(') fail("a typed parameter " + v.text + " has no arguments");
      v.items = list(depth + 1);
    } else {
      fail(std::string("unexpected '") + c + "'");
    }
    return v;
  }

  std::vector<Value> list(int depth) {
    skip();
    if (p_ >= s_.size() || s_[p_] != '(') fail("expected '('");
    ++p_;
    std::vector<Value> items;
    skip();
    if (p_ < s_.size() && s_[p_] == ')') {
      ++p_;
      return items;
    }
    for (;;) {
      items.push_back(parameter(depth));
      skip();
      if (p_ >= s_.size()) fail("text ends inside a list");
      if (s_[p_] == ',') {
        ++p_;
        continue;
      }
      if (s_[p_] == ')') {
        ++p_;
        return items;
      }
      fail("expected ',' or ')'");
    }
  }

  std::string keyword() {
    const size_t start = p_;
    while (p_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[p_])) || s_[p_] == '_' || s_[p_] == '-')) ++p_;
    std::string k = s_.substr(start, p_ - start);
    for (char& ch : k) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    return k;
  }

  long integer() {
    const size_t start = p_;
    while (p_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[p_]))) ++p_;
    if (p_ == start || p_ - start > 12) fail("an instance number is not a number");
    return std::strtol(s_.substr(start, p_ - start).c_str(), nullptr, 10);
  }

  void skip() {
    while (p_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[p_]))) ++p_;
  }
  size_t position() const { return p_; }
  [[noreturn]] void fail(const std::string& what) const { throw StepError(where_ + ": " + what); }

 private:
  const std::string& s_;
  size_t p_;
  std::string where_;
};

std::string strip_comments(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\'') in_string = !in_string;
    if (!in_string && text[i] == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      const size_t end = text.find("*/", i + 2);
      if (end == std::string::npos) break;
      i = end + 1;
      continue;
    }
    out += text[i];
  }
  return out;
}

// Millimetres per length unit: the first LENGTH_UNIT instance's SI prefix, or a conversion-based
// unit named inch; millimetres when the file names none.
double mm_per_unit(const std::map<long, Instance>& instances) {
  for (const auto& [id, inst] : instances) {
    if (inst.raw.find("LENGTH_UNIT") == std::string::npos) continue;
    std::string upper = inst.raw;
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (upper.find("CONVERSION_BASED_UNIT") != std::string::npos) {
      if (upper.find("'INCH'") != std::string::npos) return 25.4;
      if (upper.find("'FOOT'") != std::string::npos) return 304.8;
      continue;
    }
    if (upper.find("SI_UNIT(.MILLI.") != std::string::npos) return 1.0;
    if (upper.find("SI_UNIT(.CENTI.") != std::string::npos) return 10.0;
    if (upper.find("SI_UNIT(.MICRO.") != std::string::npos) return 1e-3;
    if (upper.find("SI_UNIT(.KILO.") != std::string::npos) return 1e6;
    if (upper.find("SI_UNIT($") != std::string::npos) return 1000.0;
  }
  return 1.0;
}

}  // namespace

BSplineSurface parse_step_surface(const std::string& original, const std::string& name) {
  const std::string text = strip_comments(original);
  if (text.compare(0, std::min<size_t>(text.size(), 13), "ISO-10303-21;") != 0 &&
      text.find("ISO-10303-21;") == std::string::npos) {
    throw StepError(name + ": not a STEP file (no ISO-10303-21 header)");
  }
  const size_t data = text.find("DATA;");
  if (data == std::string::npos) throw StepError(name + ": no DATA section");
  std::map<long, Instance> instances;
  size_t p = data + 5;
  for (;;) {
    while (p < text.size() && std::isspace(static_cast<unsigned char>(text[p]))) ++p;
    if (p >= text.size()) throw StepError(name + ": the DATA section does not end (ENDSEC;)");
    if (text.compare(p, 7, "ENDSEC;") == 0) break;
    if (text[p] != '#') throw StepError(name + ": expected an instance '#n=' at byte " + std::to_string(p));
    Parser head(text, p + 1, name + " (byte " + std::to_string(p) + ")");
    const long id = head.integer();
    const std::string where = name + " #" + std::to_string(id);
    head.skip();
    size_t q = head.position();
    if (q >= text.size() || text[q] != '=') throw StepError(where + ": expected '='");
    Parser body(text, q + 1, where);
    body.skip();
    Instance inst;
    q = body.position();
    if (q < text.size() && text[q] == '(') {
      // A complex instance: kept as text, the unit detection reads it.
      int depth = 0;
      size_t end = q;
      for (; end < text.size(); ++end) {
        if (text[end] == '(') ++depth;
        if (text[end] == ')' && --depth == 0) break;
      }
      if (end >= text.size()) throw StepError(where + ": a complex instance does not end");
      inst.raw = text.substr(q, end - q + 1);
      p = end + 1;
    } else {
      inst.type = body.keyword();
      if (inst.type.empty()) throw StepError(where + ": no entity name");
      inst.args = body.list(0);
      inst.raw = inst.type;
      p = body.position();
    }
    while (p < text.size() && std::isspace(static_cast<unsigned char>(text[p]))) ++p;
    if (p >= text.size() || text[p] != ';') throw StepError(where + ": expected ';' after the instance");
    ++p;
    if (!instances.emplace(id, std::move(inst)).second) throw StepError(where + ": the instance number is used twice");
  }
  const double to_mm = mm_per_unit(instances);
  // One untrimmed surface is what this reader returns: several (trimmed faces) would be measured
  // against the wrong shape, so they are refused instead.
  size_t surfaces = 0;
  for (const auto& [id, inst] : instances) surfaces += inst.type == "B_SPLINE_SURFACE_WITH_KNOTS";
  if (surfaces > 1) {
    throw StepError(name + ": the file holds " + std::to_string(surfaces) +
                    " B-spline surfaces (trimmed faces?); one untrimmed surface is read: inspect against the SURF.json "
                    "the faces were exported from");
  }
  for (const auto& [id, inst] : instances) {
    if (inst.type != "B_SPLINE_SURFACE_WITH_KNOTS") continue;
    const std::string where = name + " #" + std::to_string(id);
    const std::vector<Value>& a = inst.args;
    if (a.size() < 13) throw StepError(where + ": B_SPLINE_SURFACE_WITH_KNOTS needs 13 parameters, has " + std::to_string(a.size()));
    auto whole = [&](const Value& v, const char* what) {
      if (v.kind != Value::kNumber || v.number != std::floor(v.number) || v.number < 0 || v.number > 1e7) {
        throw StepError(where + ": " + what + " is not a whole number");
      }
      return static_cast<long>(v.number);
    };
    auto numbers = [&](const Value& v, const char* what) {
      if (v.kind != Value::kList) throw StepError(where + ": " + what + " is not a list");
      std::vector<double> out;
      for (const Value& item : v.items) {
        if (item.kind != Value::kNumber) throw StepError(where + ": " + what + " holds something that is not a number");
        out.push_back(item.number);
      }
      return out;
    };
    BSplineSurface s;
    s.degree_u = static_cast<int>(whole(a[1], "the u degree"));
    s.degree_v = static_cast<int>(whole(a[2], "the v degree"));
    const Value& net = a[3];
    if (net.kind != Value::kList || net.items.empty()) throw StepError(where + ": the control points are not a list of lists");
    s.count_u = static_cast<int>(net.items.size());
    s.count_v = -1;
    for (const Value& row : net.items) {
      if (row.kind != Value::kList) throw StepError(where + ": a row of control points is not a list");
      if (s.count_v < 0) s.count_v = static_cast<int>(row.items.size());
      if (static_cast<int>(row.items.size()) != s.count_v) throw StepError(where + ": rows of control points differ in length");
    }
    s.control.resize(static_cast<size_t>(s.count_u) * static_cast<size_t>(s.count_v));
    for (int i = 0; i < s.count_u; ++i)
      for (int j = 0; j < s.count_v; ++j) {
        const Value& r = net.items[static_cast<size_t>(i)].items[static_cast<size_t>(j)];
        const auto found = r.kind == Value::kRef ? instances.find(r.ref) : instances.end();
        if (found == instances.end() || found->second.type != "CARTESIAN_POINT" || found->second.args.size() < 2) {
          throw StepError(where + ": control point (" + std::to_string(i) + ", " + std::to_string(j) + ") is not a CARTESIAN_POINT");
        }
        const std::vector<double> xyz = numbers(found->second.args[1], "a point's coordinates");
        if (xyz.size() != 3) throw StepError(name + " #" + std::to_string(r.ref) + ": a control point needs 3 coordinates");
        s.at(i, j) = {xyz[0] * to_mm, xyz[1] * to_mm, xyz[2] * to_mm};
      }
    const std::vector<double> mu = numbers(a[8], "the u multiplicities"), mv = numbers(a[9], "the v multiplicities");
    const std::vector<double> ku = numbers(a[10], "the u knots"), kv = numbers(a[11], "the v knots");
    if (mu.size() != ku.size() || mv.size() != kv.size()) throw StepError(where + ": knots and multiplicities differ in number");
    auto expand = [&](const std::vector<double>& knots, const std::vector<double>& mult, std::vector<double>& out) {
      for (size_t k = 0; k < knots.size(); ++k) {
        if (mult[k] != std::floor(mult[k]) || mult[k] < 1 || mult[k] > 8) throw StepError(where + ": a knot multiplicity is not 1..8");
        for (int m = 0; m < static_cast<int>(mult[k]); ++m) out.push_back(knots[k]);
      }
    };
    expand(ku, mu, s.knots_u);
    expand(kv, mv, s.knots_v);
    std::string why;
    if (!is_valid(s, &why)) throw StepError(where + ": not a valid surface: " + why);
    return s;
  }
  for (const auto& [id, inst] : instances) {
    if (inst.raw.find("RATIONAL_B_SPLINE_SURFACE") != std::string::npos) {
      throw StepError(name + " #" + std::to_string(id) + ": a rational B-spline surface is not supported");
    }
  }
  throw StepError(name + ": no B_SPLINE_SURFACE_WITH_KNOTS in the file");
}

BSplineSurface read_step_surface(const std::string& path) {
  std::string text;
  if (!read_whole_file(path, &text)) throw StepError(path + ": cannot open: " + std::strerror(errno));
  return parse_step_surface(text, path);
}

}  // namespace dg::host
