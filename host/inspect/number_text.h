// Numbers as the report prints them: a value that rounds to zero has no sign ("-0.0000" and
// "+0.0000" read as a deviation that rounded away).
#pragma once
#include <cstdio>
#include <string>

namespace dg::host {

// `v` as `format` prints it (one conversion), without a sign when no digit but 0 is printed.
inline std::string number_text(double v, const char* format = "%.4f") {
  char text[48];
  std::snprintf(text, sizeof text, format, v);
  std::string out = text;
  if (!out.empty() && (out[0] == '-' || out[0] == '+') && out.find_first_of("123456789") == std::string::npos) out.erase(0, 1);
  return out;
}

}  // namespace dg::host
