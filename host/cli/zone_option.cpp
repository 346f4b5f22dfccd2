// The --zone syntax, checked part by part so the message says which part is wrong.
#include "host/cli/zone_option.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace dg::host {
namespace {

double number(const std::string& text, const std::string& zone, const char* what) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v)) {
    throw std::invalid_argument("--zone " + zone + ": " + what + " '" + text + "' is not a number");
  }
  return v;
}

// "A:B" -> {A, B}; A < B.
void pair_of(const std::string& text, const std::string& zone, const char* what, double& a, double& b) {
  const size_t colon = text.find(':');
  if (colon == std::string::npos) throw std::invalid_argument("--zone " + zone + ": " + what + " must be MIN:MAX, not '" + text + "'");
  a = number(text.substr(0, colon), zone, what);
  b = number(text.substr(colon + 1), zone, what);
  if (!(a < b)) throw std::invalid_argument("--zone " + zone + ": " + what + " " + text + " must have MIN < MAX");
}

}  // namespace

ToleranceZone parse_tolerance_zone(const std::string& text) {
  const size_t equals = text.find('=');
  ToleranceZone z;
  z.name = text.substr(0, equals);
  if (equals == std::string::npos || z.name.empty()) {
    throw std::invalid_argument("--zone '" + text + "': give NAME=X0:X1,Y0:Y1,TOL (or ...,LOWER:UPPER), mm");
  }
  for (char c : z.name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') {
      throw std::invalid_argument("--zone " + z.name + ": a name is letters, digits, '_' and '-'");
    }
  }
  const std::string rest = text.substr(equals + 1);
  const size_t first = rest.find(','), second = first == std::string::npos ? first : rest.find(',', first + 1);
  if (second == std::string::npos || rest.find(',', second + 1) != std::string::npos) {
    throw std::invalid_argument("--zone " + z.name + ": give X0:X1,Y0:Y1,TOL (or ...,LOWER:UPPER) after the name, mm");
  }
  pair_of(rest.substr(0, first), z.name, "x range", z.x0_mm, z.x1_mm);
  pair_of(rest.substr(first + 1, second - first - 1), z.name, "y range", z.y0_mm, z.y1_mm);
  const std::string tolerance = rest.substr(second + 1);
  if (tolerance.find(':') == std::string::npos) {
    const double t = number(tolerance, z.name, "tolerance");
    if (!(t > 0)) throw std::invalid_argument("--zone " + z.name + ": the tolerance must be > 0 (+-MM)");
    z.limits = {-t, t};
  } else {
    pair_of(tolerance, z.name, "tolerance", z.limits.lower_mm, z.limits.upper_mm);
  }
  return z;
}

}  // namespace dg::host
