// Reading a whole file into memory, for the readers that parse text or bytes in one piece.
#pragma once
#include <fstream>
#include <string>

namespace dg::host {

// False when the file cannot be opened (errno says why); the caller names the file in its error.
// Read in blocks of 1 MB (a character at a time took a sixth of reading a million-point CSV); a
// regular file's size reserves the memory first, and a pipe, which has none, is read to its end.
inline bool read_whole_file(const std::string& path, std::string* bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  bytes->clear();
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size > 0) bytes->reserve(static_cast<size_t>(size));
  in.clear();
  in.seekg(0, std::ios::beg);
  in.clear();
  constexpr size_t kBlock = size_t{1} << 20;
  for (;;) {
    const size_t used = bytes->size();
    bytes->resize(used + kBlock);
    in.read(&(*bytes)[used], static_cast<std::streamsize>(kBlock));
    bytes->resize(used + static_cast<size_t>(in.gcount()));
    if (!in) break;
  }
  return true;
}

}  // namespace dg::host
