// Extension tests without locale: only ASCII letters fold, so a name in UTF-8 is never changed.
#include "host/io/file_name.h"

#include <cstring>

namespace dg::host {
namespace {

char lower(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }

}  // namespace

bool ends_with(const std::string& text, const char* suffix) {
  const size_t n = std::strlen(suffix);
  if (text.size() < n) return false;
  for (size_t i = 0; i < n; ++i) {
    if (lower(text[text.size() - n + i]) != lower(suffix[i])) return false;
  }
  return true;
}

FileFormat file_format(const std::string& path) {
  struct Extension {
    const char* suffix;
    FileFormat format;
  };
  static const Extension kExtensions[] = {
      {".scan", FileFormat::kScan}, {".csv", FileFormat::kCsv},   {".xyz", FileFormat::kXyz},
      {".txt", FileFormat::kText},   {".ply", FileFormat::kPly},   {".json", FileFormat::kJson},
      {".igs", FileFormat::kIges},  {".iges", FileFormat::kIges}, {".stp", FileFormat::kStep},
      {".step", FileFormat::kStep}, {".stl", FileFormat::kStl},   {".obj", FileFormat::kObj},
      {".html", FileFormat::kHtml}, {".htm", FileFormat::kHtml},
      {".probe", FileFormat::kBcncProbe}, {".map", FileFormat::kCandleMap}, {".cfg", FileFormat::kKlipperMesh},
  };
  for (const Extension& e : kExtensions) {
    if (ends_with(path, e.suffix)) return e.format;
  }
  return FileFormat::kUnknown;
}

std::string base_name(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string without_extension(const std::string& path) {
  const size_t dot = path.find_last_of('.');
  const size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path;
  return path.substr(0, dot);
}

}  // namespace dg::host
