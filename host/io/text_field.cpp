// Strict decimal numbers and safe quoting of bad fields.
#include "host/io/text_field.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace dg::host {

bool parse_decimal(const std::string& field, double* value) {
  size_t i = 0, n = field.size();
  while (i < n && (field[i] == ' ' || field[i] == '\t')) ++i;
  while (n > i && (field[n - 1] == ' ' || field[n - 1] == '\t' || field[n - 1] == '\r')) --n;
  const size_t start = i;
  if (i < n && (field[i] == '+' || field[i] == '-')) ++i;
  size_t digits = 0;
  while (i < n && field[i] >= '0' && field[i] <= '9') ++i, ++digits;
  if (i < n && field[i] == '.') {
    ++i;
    while (i < n && field[i] >= '0' && field[i] <= '9') ++i, ++digits;
  }
  if (digits == 0) return false;
  if (i < n && (field[i] == 'e' || field[i] == 'E')) {
    ++i;
    if (i < n && (field[i] == '+' || field[i] == '-')) ++i;
    size_t exponent_digits = 0;
    while (i < n && field[i] >= '0' && field[i] <= '9') ++i, ++exponent_digits;
    if (exponent_digits == 0) return false;
  }
  if (i != n) return false;  // anything else, an embedded NUL included
  const std::string text = field.substr(start, n - start);
  errno = 0;
  const double v = std::strtod(text.c_str(), nullptr);
  // ERANGE with a finite result is underflow (a denormal or 0): a valid, tiny number.
  if (!std::isfinite(v)) return false;
  *value = v;
  return true;
}

std::string quoted(const std::string& field) {
  constexpr size_t kShown = 80;
  std::string out = "'";
  for (size_t i = 0; i < field.size() && i < kShown; ++i) {
    const unsigned char c = static_cast<unsigned char>(field[i]);
    if (c < 0x20 || c == 0x7f) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", c);
      out += escaped;
    } else {
      out += static_cast<char>(c);
    }
  }
  out += "'";
  if (field.size() > kShown) out += " (cut; " + std::to_string(field.size()) + " characters)";
  return out;
}

}  // namespace dg::host
