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

// Every writer holds an exclusive lock (flock) on its file while it writes: a second writer of the
// same file is refused, whichever way it opens it.
class ScanFileWriter : public ScanSink {
 public:
  // Creates `path` now; an existing file is an error (nothing is replaced).
  explicit ScanFileWriter(const std::string& path);
  // A new scan file that appears at `path` only when the device has accepted the scan (accepted()):
  // until then the records go to a hidden file beside it, removed if the scan never starts. With
  // `replace`, an existing regular file at `path` is replaced at that moment, in one rename;
  // without, a file that appeared there meanwhile (another scan) is an error.
  static ScanFileWriter when_accepted(const std::string& path, bool replace);
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
  // Appends a record that names the table calibration (its JSON text) correcting this scan's points;
  // the points stay raw in the file, and a later record replaces an earlier one (re-correction).
  void append_calibration(const std::string& json);
  // Forces everything appended so far to the disk (fdatasync).
  void sync() override;
  void accepted() override;
  const std::string& path() const override { return path_; }
  uint64_t bytes_written() const { return bytes_; }

 private:
  ScanFileWriter() = default;
  void lock_or_throw();
  void write_record(const uint8_t* record, size_t size);
  std::string path_;
  std::string pending_;  // the hidden file until accepted(); empty once the file is at path_
  bool replace_ = false;
  int fd_ = -1;
  uint64_t bytes_ = 0;
};

// How the points of a scan of several passes come back: in rows (y, then x; a line a row), or as
// stored (for resuming the last pass).
enum class ScanOrder { kRows, kAsStored };

// Reads a whole scan file. A damaged record in the middle is an error naming the
// byte offset; a cut-off final record (a crash while writing) is a warning.
ScanData read_scan_file(const std::string& path, ScanOrder order = ScanOrder::kRows);
// The same on bytes already in memory; `name` is used in messages.
ScanData parse_scan_bytes(const uint8_t* bytes, size_t size, const std::string& name, ScanOrder order = ScanOrder::kRows);

}  // namespace dg::host
