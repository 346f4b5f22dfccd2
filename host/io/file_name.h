// File names as the commands read them: the extension picks a format, messages name the file.
#pragma once
#include <cstring>
#include <string>

namespace dg::host {

// Exact (case-sensitive) suffix test: ends_with("part.igs", ".igs").
inline bool ends_with(const std::string& text, const char* suffix) {
  const size_t n = std::strlen(suffix);
  return text.size() >= n && text.compare(text.size() - n, n, suffix) == 0;
}

// The last component of a path: base_name("out/part.igs") is "part.igs".
inline std::string base_name(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

}  // namespace dg::host
