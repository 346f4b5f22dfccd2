// Reading a whole file into memory, for the readers that parse text or bytes in one piece.
#pragma once
#include <fstream>
#include <iterator>
#include <string>

namespace dg::host {

// False when the file cannot be opened (errno says why); the caller names the file in its error.
inline bool read_whole_file(const std::string& path, std::string* bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  bytes->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return true;
}

}  // namespace dg::host
