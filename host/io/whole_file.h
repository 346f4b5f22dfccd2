// Reading a whole file into memory, for the readers that parse text or bytes in one piece.
#pragma once
#include <cstddef>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>

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

// A whole file's bytes for the point readers, which parse a view of them: read into memory that is
// not zeroed first (a std::string's resize zeroes what the read then overwrites, and for a
// million-point file that pass and its page faults took 0.03-0.06 s, as long as parsing a PLY).
// Not a mapping of the file: one that shrinks while it is read would stop the program with SIGBUS.
class FileBytes {
 public:
  // False when the file cannot be opened or read (errno says why).
  bool read(const std::string& path);
  std::string_view view() const { return {data_.get(), size_}; }

 private:
  std::unique_ptr<char[]> data_;
  size_t size_ = 0;
};

}  // namespace dg::host
