// The --zone syntax, checked part by part so the message says which part is wrong.
#include "host/cli/zone_option.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <vector>

namespace dg::host {
namespace {

// Messages name the option and the region: "--zone seal: ...".
struct Context {
  const char* option;
  std::string name;
  std::string operator()(const std::string& what) const { return std::string(option) + " " + name + ": " + what; }
};

double number(const std::string& text, const Context& at, const char* what) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v)) {
    throw std::invalid_argument(at(std::string(what) + " '" + text + "' is not a number"));
  }
  return v;
}

// "A:B" -> {A, B}; A < B.
void pair_of(const std::string& text, const Context& at, const char* what, double& a, double& b) {
  const size_t colon = text.find(':');
  if (colon == std::string::npos) throw std::invalid_argument(at(std::string(what) + " must be MIN:MAX, not '" + text + "'"));
  a = number(text.substr(0, colon), at, what);
  b = number(text.substr(colon + 1), at, what);
  if (!(a < b)) throw std::invalid_argument(at(std::string(what) + " " + text + " must have MIN < MAX"));
}

// NAME=X0:X1,Y0:Y1 then `parts_after` more comma-separated parts, returned in `after`.
ToleranceZone named_box(const std::string& text, const char* option, const char* form, size_t parts_after,
                        std::vector<std::string>& after) {
  const size_t equals = text.find('=');
  ToleranceZone z;
  z.name = text.substr(0, equals);
  if (equals == std::string::npos || z.name.empty()) {
    throw std::invalid_argument(std::string(option) + " '" + text + "': give NAME=" + form + ", mm");
  }
  const Context at{option, z.name};
  for (char c : z.name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') throw std::invalid_argument(at("a name is letters, digits, '_' and '-'"));
  }
  std::vector<std::string> parts;
  const std::string rest = text.substr(equals + 1);
  for (size_t from = 0;;) {
    const size_t comma = rest.find(',', from);
    parts.push_back(rest.substr(from, comma == std::string::npos ? std::string::npos : comma - from));
    if (comma == std::string::npos) break;
    from = comma + 1;
  }
  if (parts.size() != 2 + parts_after) throw std::invalid_argument(at(std::string("give ") + form + " after the name, mm"));
  pair_of(parts[0], at, "x range", z.x0_mm, z.x1_mm);
  pair_of(parts[1], at, "y range", z.y0_mm, z.y1_mm);
  after.assign(parts.begin() + 2, parts.end());
  return z;
}

}  // namespace

ToleranceZone parse_tolerance_zone(const std::string& text) {
  std::vector<std::string> after;
  ToleranceZone z = named_box(text, "--zone", "X0:X1,Y0:Y1,TOL (or ...,LOWER:UPPER)", 1, after);
  const Context at{"--zone", z.name};
  const std::string& tolerance = after[0];
  if (tolerance.find(':') == std::string::npos) {
    const double t = number(tolerance, at, "tolerance");
    if (!(t > 0)) throw std::invalid_argument(at("the tolerance must be > 0 (+-MM)"));
    z.limits = {-t, t};
  } else {
    pair_of(tolerance, at, "tolerance", z.limits.lower_mm, z.limits.upper_mm);
  }
  return z;
}

ToleranceZone parse_datum_region(const std::string& text) {
  std::vector<std::string> after;
  return named_box(text, "--datum", "X0:X1,Y0:Y1", 0, after);
}

}  // namespace dg::host
