// Scan file records are encoded with nanopb: field 1 of ScanFile, holding a ScanRecord
// (the Envelope and a CRC-32 of its encoded bytes).
#include "host/scan/scan_file.h"
#include "host/io/whole_file.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <pb_decode.h>
#include <pb_encode.h>
#include <unistd.h>

#include <algorithm>
#include <optional>
#include <cerrno>
#include <cstring>
#include <vector>

#include "common/link/crc32.h"
#include "common/proto/messages.h"

namespace dg::host {

// ScanFile.record's field number (ScanFile itself is skipped by nanopb: our code
// reads records one at a time).
constexpr uint32_t kScanFileRecordTag = 1;
constexpr uint32_t kScanRecordCalibrationTag = 3;  // ScanRecord.calibration (FT_IGNORE in the generated code)

namespace {

std::string directory_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
}

// Makes a rename or link in `directory` durable.
void sync_directory(const std::string& directory) {
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  fsync(fd);
  ::close(fd);
}

}  // namespace

void ScanFileWriter::lock_or_throw() {
  if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    ::close(fd_);
    fd_ = -1;
    if (error == EWOULDBLOCK) {
      throw ScanFileError(path_ + ": another digitizer process is writing this scan file (it holds its lock); "
                          "wait for it to finish or stop it");
    }
    throw ScanFileError(path_ + ": cannot lock: " + std::strerror(error));
  }
}

ScanFileWriter::ScanFileWriter(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_APPEND | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw ScanFileError(path + (errno == EEXIST ? ": exists already; a scan file is never replaced without asking"
                                                : ": cannot create: " + std::string(std::strerror(errno))));
  }
  lock_or_throw();
}

ScanFileWriter ScanFileWriter::when_accepted(const std::string& path, bool replace) {
  ScanFileWriter writer;
  writer.path_ = path;
  writer.replace_ = replace;
  struct stat existing {};
  if (::stat(path.c_str(), &existing) == 0) {
    if (!S_ISREG(existing.st_mode)) throw ScanFileError(path + ": exists and is not a regular file; a scan file cannot go there");
    if (!replace) throw ScanFileError(path + ": exists already; a scan file is never replaced without asking");
    // A file another process is still writing is not replaced under it.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd >= 0) {
      const bool busy = flock(fd, LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK;
      ::close(fd);
      if (busy) throw ScanFileError(path + ": another digitizer process is writing this scan file; it is not replaced");
    }
  }
  const std::string directory = directory_of(path);
  const size_t slash = path.find_last_of('/');
  std::string pattern = directory + "/." + (slash == std::string::npos ? path : path.substr(slash + 1)) + ".XXXXXX";
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  writer.fd_ = mkostemp(name.data(), O_APPEND | O_CLOEXEC);
  if (writer.fd_ < 0) throw ScanFileError(path + ": cannot create a file in " + directory + ": " + std::strerror(errno));
  writer.pending_ = name.data();
  fchmod(writer.fd_, 0644);
  writer.lock_or_throw();
  return writer;
}

void ScanFileWriter::accepted() {
  if (pending_.empty()) return;
  sync();
  if (replace_) {
    if (::rename(pending_.c_str(), path_.c_str()) != 0) {
      throw ScanFileError(path_ + ": cannot put the scan in place: " + std::strerror(errno) + "; it is in " + pending_);
    }
  } else {
    // link(2) fails if the name exists: a scan file that appeared meanwhile is not replaced.
    if (::link(pending_.c_str(), path_.c_str()) != 0) {
      throw ScanFileError(path_ + (errno == EEXIST ? ": another scan created this file meanwhile; this scan's points are in " + pending_
                                                   : ": cannot put the scan in place: " + std::string(std::strerror(errno)) +
                                                         "; it is in " + pending_));
    }
    ::unlink(pending_.c_str());
  }
  sync_directory(directory_of(path_));
  pending_.clear();
}

ScanFileWriter ScanFileWriter::continue_file(const std::string& path, uint64_t keep_bytes) {
  ScanFileWriter writer;
  writer.path_ = path;
  writer.fd_ = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (writer.fd_ < 0) throw ScanFileError(path + ": cannot open to continue: " + std::strerror(errno));
  writer.lock_or_throw();
  if (ftruncate(writer.fd_, static_cast<off_t>(keep_bytes)) != 0) {
    throw ScanFileError(path + ": cannot cut off the damaged end: " + std::strerror(errno));
  }
  writer.bytes_ = keep_bytes;
  return writer;
}

ScanFileWriter::ScanFileWriter(ScanFileWriter&& other) noexcept
    : path_(std::move(other.path_)), pending_(std::move(other.pending_)), replace_(other.replace_), fd_(other.fd_),
      bytes_(other.bytes_) {
  other.fd_ = -1;
  other.pending_.clear();
}

ScanFileWriter::~ScanFileWriter() {
  if (fd_ >= 0) {
    fsync(fd_);
    ::close(fd_);
  }
  // A scan the device never accepted leaves nothing behind.
  if (!pending_.empty()) ::unlink(pending_.c_str());
}

void ScanFileWriter::append(const digitizer_Envelope& message) {
  uint8_t envelope[digitizer_Envelope_size];
  size_t envelope_size = 0;
  if (encode_envelope(message, envelope, sizeof(envelope), &envelope_size) != Status::kOk) {
    throw ScanFileError(path_ + ": cannot encode a record");
  }
  digitizer_ScanRecord record = digitizer_ScanRecord_init_zero;
  record.has_message = true;
  record.message = message;
  record.crc32 = crc32(envelope, envelope_size);
  uint8_t buffer[digitizer_ScanRecord_size + 8];
  pb_ostream_t inner = pb_ostream_from_buffer(buffer + 8, digitizer_ScanRecord_size);
  if (!pb_encode(&inner, digitizer_ScanRecord_fields, &record)) {
    throw ScanFileError(path_ + ": cannot encode a record: " + PB_GET_ERROR(&inner));
  }
  write_record(buffer + 8, inner.bytes_written);
}

void ScanFileWriter::append_calibration(const std::string& json) {
  // ScanRecord { calibration = 3 (bytes); crc32 = 2 }, encoded field by field (the generated struct
  // leaves the field out: the device never carries it).
  std::vector<uint8_t> record(json.size() + 32);
  pb_ostream_t inner = pb_ostream_from_buffer(record.data(), record.size());
  if (!pb_encode_tag(&inner, PB_WT_STRING, kScanRecordCalibrationTag) ||
      !pb_encode_string(&inner, reinterpret_cast<const pb_byte_t*>(json.data()), json.size()) ||
      !pb_encode_tag(&inner, PB_WT_32BIT, digitizer_ScanRecord_crc32_tag)) {
    throw ScanFileError(path_ + ": cannot encode the calibration record");
  }
  const uint32_t crc = crc32(reinterpret_cast<const uint8_t*>(json.data()), json.size());
  if (!pb_encode_fixed32(&inner, &crc)) throw ScanFileError(path_ + ": cannot encode the calibration record");
  write_record(record.data(), inner.bytes_written);
}

void ScanFileWriter::write_record(const uint8_t* record, size_t size) {
  // Prefix: ScanFile field 1, length-delimited; one write(2) for prefix and record together.
  uint8_t prefix[16];
  pb_ostream_t head = pb_ostream_from_buffer(prefix, sizeof(prefix));
  pb_encode_tag(&head, PB_WT_STRING, kScanFileRecordTag);
  pb_encode_varint(&head, size);
  std::vector<uint8_t> whole(prefix, prefix + head.bytes_written);
  whole.insert(whole.end(), record, record + size);
  const size_t total = whole.size();
  size_t done = 0;
  while (done < total) {
    const ssize_t n = ::write(fd_, whole.data() + done, total - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw ScanFileError(path_ + ": write failed: " + std::strerror(errno));
    done += static_cast<size_t>(n);
  }
  bytes_ += total;
}

void ScanFileWriter::sync() {
  if (fdatasync(fd_) != 0 && errno != EINVAL) {
    throw ScanFileError(path_ + ": fdatasync failed: " + std::strerror(errno));
  }
}

namespace {

// Where the current pass's points begin in data->points: sequence numbers are checked within a
// pass (the device may have restarted between two).
struct PassState {
  size_t first_point = 0;
  std::optional<digitizer_ScanDone> previous_done;  // the pass before's end
};

void take(ScanData* data, const digitizer_Envelope& message, const std::string& where, PassState* pass) {
  switch (message.which_body) {
    // A scan file holds one scan: a second Hello or request is two files joined (cat a b > c),
    // whose points would read back as one scan.
    case digitizer_Envelope_hello_tag:
      if (data->device) throw ScanFileError(where + ": a second device hello: two scan files joined into one?");
      data->device = message.body.hello;
      break;
    case digitizer_Envelope_scan_request_tag:
      // A further pass of an adaptive scan begins only after the one before it ended; a second
      // request in the middle of a scan is two files joined.
      // A pass the device refused left its request and nothing else: the next one takes its place.
      if (data->passes.size() > 1 && !data->done && data->points.size() == pass->first_point) data->passes.pop_back();
      else if (data->request && !data->done) throw ScanFileError(where + ": a second scan request: two scan files joined into one?");
      if (!data->request) data->request = message.body.scan_request;
      data->passes.push_back(message.body.scan_request);
      if (data->done) pass->previous_done = data->done;
      data->done.reset();
      pass->first_point = data->points.size();
      break;
    case digitizer_Envelope_repeatability_tag:
      if (data->repeatability) throw ScanFileError(where + ": a second repeatability record: two scan files joined into one?");
      data->repeatability = message.body.repeatability;
      break;
    case digitizer_Envelope_points_tag: {
      PointSample batch[kMaxPointsPerBatch];
      size_t count = 0;
      if (point_batch_expand(message.body.points, batch, &count) != Status::kOk) {
        throw ScanFileError(where + ": point batch is inconsistent");
      }
      for (size_t i = 0; i < count; ++i) {
        if (data->points.size() > pass->first_point && batch[i].seq != data->points.back().seq + 1) {
          if (batch[i].seq <= data->points.back().seq) continue;  // stored twice: keep once
          data->warnings.push_back(where + ": points " + std::to_string(data->points.back().seq + 1) +
                                   " to " + std::to_string(batch[i].seq - 1) + " are missing");
        }
        data->points.push_back(batch[i]);
      }
      break;
    }
    case digitizer_Envelope_line_done_tag:
      data->lines.push_back(message.body.line_done);
      break;
    case digitizer_Envelope_scan_done_tag:
      data->done = message.body.scan_done;
      data->device_time_us += message.body.scan_done.duration_us;
      break;
    case digitizer_Envelope_fault_tag:
      data->faults.push_back(message.body.fault);
      break;
    default:
      break;  // other messages are kept in the file but carry no scan data
  }
}

// An adaptive scan's passes each add short runs of points: readers want rows, so the points are
// put in order of y then x and each distinct y becomes a line, its first and last points flagged.
void by_rows(ScanData* data) {
  std::stable_sort(data->points.begin(), data->points.end(), [](const PointSample& a, const PointSample& b) {
    return a.y_nm != b.y_nm ? a.y_nm < b.y_nm : a.x_nm < b.x_nm;
  });
  const uint32_t ends = digitizer_PointFlag_POINT_LINE_START | digitizer_PointFlag_POINT_LINE_END;
  uint32_t line = 0;
  for (size_t i = 0; i < data->points.size(); ++i) {
    PointSample& p = data->points[i];
    if (i > 0 && p.y_nm != data->points[i - 1].y_nm) ++line;
    p.line = line;
    p.flags &= ~ends;
    if (i == 0 || p.y_nm != data->points[i - 1].y_nm) p.flags |= digitizer_PointFlag_POINT_LINE_START;
    if (i + 1 == data->points.size() || p.y_nm != data->points[i + 1].y_nm) p.flags |= digitizer_PointFlag_POINT_LINE_END;
  }
}

}  // namespace

ScanData read_scan_file(const std::string& path, ScanOrder order) {
  std::string bytes;
  if (!read_whole_file(path, &bytes)) throw ScanFileError(path + ": cannot open: " + std::strerror(errno));
  return parse_scan_bytes(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), path, order);
}

ScanData parse_scan_bytes(const uint8_t* bytes, size_t size, const std::string& path, ScanOrder order) {
  ScanData data;
  PassState pass;
  size_t offset = 0;
  while (offset < size) {
    const std::string where = path + ": record " + std::to_string(data.records + 1) +
                              " at byte " + std::to_string(offset);
    pb_istream_t stream = pb_istream_from_buffer(bytes + offset, size - offset);
    pb_wire_type_t wire_type;
    uint32_t tag = 0;
    bool eof = false;
    uint64_t length = 0;
    if (!pb_decode_tag(&stream, &wire_type, &tag, &eof) || !pb_decode_varint(&stream, &length)) {
      data.warnings.push_back(where + ": file ends inside a record header (cut off while writing?)");
      break;
    }
    if (tag != kScanFileRecordTag || wire_type != PB_WT_STRING) {
      throw ScanFileError(where + ": not a scan-file record (is this a scan file?)");
    }
    const size_t header = (size - offset) - stream.bytes_left;
    if (length > stream.bytes_left) {
      data.warnings.push_back(where + ": last record is cut off (" + std::to_string(stream.bytes_left) +
                              " of " + std::to_string(length) + " bytes); it is ignored");
      break;
    }
    // Inside the record: field 1 = Envelope bytes, field 2 = CRC-32 of those bytes.
    const uint8_t* record = bytes + offset + header;
    pb_istream_t inner = pb_istream_from_buffer(record, static_cast<size_t>(length));
    const uint8_t* envelope_bytes = nullptr;
    uint64_t envelope_size = 0;
    const uint8_t* calibration_bytes = nullptr;
    uint64_t calibration_size = 0;
    uint32_t stored_crc = 0;
    bool has_crc = false;
    while (inner.bytes_left > 0) {
      if (!pb_decode_tag(&inner, &wire_type, &tag, &eof)) {
        throw ScanFileError(where + ": damaged record");
      }
      if (tag == digitizer_ScanRecord_message_tag && wire_type == PB_WT_STRING) {
        if (!pb_decode_varint(&inner, &envelope_size) || envelope_size > inner.bytes_left) {
          throw ScanFileError(where + ": damaged record");
        }
        envelope_bytes = record + (length - inner.bytes_left);
        if (!pb_read(&inner, nullptr, static_cast<size_t>(envelope_size))) {
          throw ScanFileError(where + ": damaged record");
        }
      } else if (tag == kScanRecordCalibrationTag && wire_type == PB_WT_STRING) {
        if (!pb_decode_varint(&inner, &calibration_size) || calibration_size > inner.bytes_left) {
          throw ScanFileError(where + ": damaged record");
        }
        calibration_bytes = record + (length - inner.bytes_left);
        if (!pb_read(&inner, nullptr, static_cast<size_t>(calibration_size))) throw ScanFileError(where + ": damaged record");
      } else if (tag == digitizer_ScanRecord_crc32_tag && wire_type == PB_WT_32BIT) {
        if (!pb_decode_fixed32(&inner, &stored_crc)) throw ScanFileError(where + ": damaged record");
        has_crc = true;
      } else if (!pb_skip_field(&inner, wire_type)) {
        throw ScanFileError(where + ": damaged record");
      }
    }
    if (calibration_bytes != nullptr && envelope_bytes == nullptr && has_crc) {
      if (crc32(calibration_bytes, static_cast<size_t>(calibration_size)) != stored_crc) {
        throw ScanFileError(where + ": CRC mismatch in the calibration record (the file is damaged)");
      }
      data.calibration_json.emplace(reinterpret_cast<const char*>(calibration_bytes), static_cast<size_t>(calibration_size));
      ++data.records;
      offset += header + static_cast<size_t>(length);
      data.complete_bytes = offset;
      continue;
    }
    if (envelope_bytes == nullptr || !has_crc) {
      throw ScanFileError(where + ": record without message or CRC");
    }
    if (crc32(envelope_bytes, static_cast<size_t>(envelope_size)) != stored_crc) {
      throw ScanFileError(where + ": CRC mismatch (the file is damaged)");
    }
    digitizer_Envelope message;
    if (decode_envelope(envelope_bytes, static_cast<size_t>(envelope_size), &message) != Status::kOk) {
      throw ScanFileError(where + ": message does not decode");
    }
    take(&data, message, where, &pass);
    ++data.records;
    offset += header + static_cast<size_t>(length);
    data.complete_bytes = offset;
  }
  // A last pass the device refused (its request and nothing after it): the scan ended with the one before.
  if (data.passes.size() > 1 && !data.done && data.points.size() == pass.first_point && pass.previous_done) {
    data.passes.pop_back();
    data.done = pass.previous_done;
  }
  data.last_pass_first_point = pass.first_point;
  if (data.passes.size() > 1 && order == ScanOrder::kRows) by_rows(&data);
  return data;
}

}  // namespace dg::host
