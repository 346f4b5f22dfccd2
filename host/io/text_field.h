// Numbers and quotes in text files from outside: decimal numbers only, and error messages that
// quote a bad field briefly and without the control characters it may carry.
#pragma once
#include <string>
#include <string_view>

namespace dg::host {

// A decimal number: optional sign, digits with an optional point, an optional exponent; spaces
// and tabs around it. No hexadecimal ("0x10"), no "inf" or "nan", no embedded NUL. A value too
// small for a normal double (a denormal, or one that rounds to 0) is accepted; one too large is
// not (it is not finite). True and *value on success.
bool parse_decimal(std::string_view field, double* value);

// `field` for an error message: at most 80 characters (longer is cut, with its length said), and
// control characters (a terminal's escape sequences, NUL) shown as \xNN.
std::string quoted(std::string_view field);
// The same for a std::string, so a call with one is not taken by std::quoted (<iomanip>) through
// argument-dependent lookup.
inline std::string quoted(const std::string& field) { return quoted(std::string_view(field)); }

}  // namespace dg::host
