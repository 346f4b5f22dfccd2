// Parsing millimetre values and ranges from the command line into integer nanometres.
#pragma once
#include <cstdint>
#include <string>

namespace dg::host {

// 12.5 -> 12500000, rounded to the nearest nanometre. Throws std::invalid_argument
// naming `what` for a value that is not finite or beyond +-2147 mm.
int32_t mm_to_nm(double mm, const std::string& what);
// "12.5" -> 12500000. Throws std::invalid_argument naming `what` for bad input.
int32_t parse_mm(const std::string& text, const std::string& what);
// "0:40" -> {0, 40000000}; min must not exceed max.
struct RangeNm {
  int32_t min_nm = 0;
  int32_t max_nm = 0;
};
RangeNm parse_range_mm(const std::string& text, const std::string& what);

}  // namespace dg::host
