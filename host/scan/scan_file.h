// Scan files: an append-only sequence of ScanRecord messages (see docs/scan-file.md).
#pragma once
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "digitizer.pb.h"
#include "host/scan/scan_sink.h"

namespace dg::host {

// A scan file could not be written or read; the message names the file and where.
class ScanFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ScanFileWriter : public ScanSink {
 public:
  // Creates (or truncates) the file.
  explicit ScanFileWriter(const std::string& path);
  // Opens an existing file to continue it: cuts it to its first `keep_bytes` (the whole records a
  // reader found; a record cut off by a crash goes) and appends after them.
  static ScanFileWriter continue_file(const std::string& path, uint64_t keep_bytes);
  ScanFileWriter(ScanFileWriter&& other) noexcept;
  ~ScanFileWriter() override;
  ScanFileWriter(const ScanFileWriter&) = delete;
  ScanFileWriter& operator=(const ScanFileWriter&) = delete;

  // Appends one record with a single write(2): a crash leaves whole records and at
  // most one cut-off record at the end, which readers detect and skip.
  void append(const digitizer_Envelope& message) override;
  // Forces everything appended so far to the disk (at each line's end).
  void sync() override;
  const std::string& path() const override { return path_; }
  uint64_t bytes_written() const { return bytes_; }

 private:
  ScanFileWriter() = default;
  std::string path_;
  int fd_ = -1;
  uint64_t bytes_ = 0;
};


// Reads a whole scan file. A damaged record in the middle is an error naming the
// byte offset; a cut-off final record (a crash while writing) is a warning.
ScanData read_scan_file(const std::string& path);
// The same on bytes already in memory; `name` is used in messages.
ScanData parse_scan_bytes(const uint8_t* bytes, size_t size, const std::string& name);

}  // namespace dg::host
