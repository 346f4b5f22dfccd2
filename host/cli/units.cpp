// Millimetre parsing with range checks; no silent truncation.
#include "host/cli/units.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace dg::host {

int32_t mm_to_nm(double mm, const std::string& what) {
  const double nm = std::round(mm * 1e6);
  if (!std::isfinite(nm) || nm > 2147483647.0 || nm < -2147483648.0) {
    throw std::invalid_argument(what + ": " + std::to_string(mm) + " mm is beyond +-2147 mm");
  }
  return static_cast<int32_t>(nm);
}

int32_t parse_mm(const std::string& text, const std::string& what) {
  char* end = nullptr;
  errno = 0;
  const double mm = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno != 0 || !std::isfinite(mm)) {
    throw std::invalid_argument(what + ": '" + text + "' is not a number of millimetres");
  }
  return mm_to_nm(mm, what);
}

RangeNm parse_range_mm(const std::string& text, const std::string& what) {
  const size_t colon = text.find(':');
  if (colon == std::string::npos) {
    throw std::invalid_argument(what + ": expected MIN:MAX in mm, got '" + text + "'");
  }
  RangeNm r;
  r.min_nm = parse_mm(text.substr(0, colon), what);
  r.max_nm = parse_mm(text.substr(colon + 1), what);
  if (r.max_nm < r.min_nm) throw std::invalid_argument(what + ": max is below min in '" + text + "'");
  return r;
}

}  // namespace dg::host
