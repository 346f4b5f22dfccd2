// Strict decimal numbers and safe quoting of bad fields.
#include "host/io/text_field.h"

#include <cerrno>
#include <charconv>
#include <string>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace dg::host {

bool parse_decimal(std::string_view field, double* value) {
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
  // The grammar is checked: std::from_chars reads it exactly, without a copy or the locale (it
  // takes no '+'). Only a value out of range goes the slow way, where strtod tells underflow (a
  // tiny number, kept) from overflow (refused below).
  const size_t digits_start = field[start] == '+' ? start + 1 : start;
  double v = 0;
  const auto [end, error] = std::from_chars(field.data() + digits_start, field.data() + n, v);
  if (error == std::errc::result_out_of_range) {
    const std::string text(field.substr(start, n - start));
    v = std::strtod(text.c_str(), nullptr);
  } else if (error != std::errc() || end != field.data() + n) {
    return false;
  }
  // ERANGE with a finite result is underflow (a denormal or 0): a valid, tiny number.
  if (!std::isfinite(v)) return false;
  *value = v;
  return true;
}

std::string quoted(std::string_view field) {
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
