// Scan file records are encoded with nanopb: field 1 of ScanFile, holding a ScanRecord
// (the Envelope and a CRC-32 of its encoded bytes).
#include "host/scan/scan_file.h"
#include "host/io/whole_file.h"

#include <fcntl.h>
#include <pb_decode.h>
#include <pb_encode.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "common/link/crc32.h"
#include "common/proto/messages.h"

namespace dg::host {

// ScanFile.record's field number (ScanFile itself is skipped by nanopb: our code
// reads records one at a time).
constexpr uint32_t kScanFileRecordTag = 1;

ScanFileWriter::ScanFileWriter(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0644);
  if (fd_ < 0) throw ScanFileError(path + ": cannot create: " + std::strerror(errno));
}

ScanFileWriter ScanFileWriter::continue_file(const std::string& path, uint64_t keep_bytes) {
  ScanFileWriter writer;
  writer.path_ = path;
  writer.fd_ = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (writer.fd_ < 0) throw ScanFileError(path + ": cannot open to continue: " + std::strerror(errno));
  if (ftruncate(writer.fd_, static_cast<off_t>(keep_bytes)) != 0) {
    throw ScanFileError(path + ": cannot cut off the damaged end: " + std::strerror(errno));
  }
  writer.bytes_ = keep_bytes;
  return writer;
}

ScanFileWriter::ScanFileWriter(ScanFileWriter&& other) noexcept
    : path_(std::move(other.path_)), fd_(other.fd_), bytes_(other.bytes_) {
  other.fd_ = -1;
}

ScanFileWriter::~ScanFileWriter() {
  if (fd_ >= 0) {
    fsync(fd_);
    ::close(fd_);
  }
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
  // Prefix: ScanFile field 1, length-delimited.
  uint8_t prefix[8];
  pb_ostream_t head = pb_ostream_from_buffer(prefix, sizeof(prefix));
  pb_encode_tag(&head, PB_WT_STRING, kScanFileRecordTag);
  pb_encode_varint(&head, inner.bytes_written);
  uint8_t* start = buffer + 8 - head.bytes_written;
  std::memcpy(start, prefix, head.bytes_written);
  const size_t total = head.bytes_written + inner.bytes_written;
  size_t done = 0;
  while (done < total) {
    const ssize_t n = ::write(fd_, start + done, total - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw ScanFileError(path_ + ": write failed: " + std::strerror(errno));
    done += static_cast<size_t>(n);
  }
  bytes_ += total;
}

void ScanFileWriter::sync() {
  if (fsync(fd_) != 0 && errno != EINVAL) {
    throw ScanFileError(path_ + ": fsync failed: " + std::strerror(errno));
  }
}

namespace {

void take(ScanData* data, const digitizer_Envelope& message, const std::string& where) {
  switch (message.which_body) {
    case digitizer_Envelope_hello_tag:
      data->device = message.body.hello;
      break;
    case digitizer_Envelope_scan_request_tag:
      data->request = message.body.scan_request;
      break;
    case digitizer_Envelope_points_tag: {
      PointSample batch[kMaxPointsPerBatch];
      size_t count = 0;
      if (point_batch_expand(message.body.points, batch, &count) != Status::kOk) {
        throw ScanFileError(where + ": point batch is inconsistent");
      }
      for (size_t i = 0; i < count; ++i) {
        if (!data->points.empty() && batch[i].seq != data->points.back().seq + 1) {
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
      break;
    case digitizer_Envelope_fault_tag:
      data->faults.push_back(message.body.fault);
      break;
    default:
      break;  // other messages are kept in the file but carry no scan data
  }
}

}  // namespace

ScanData read_scan_file(const std::string& path) {
  std::string bytes;
  if (!read_whole_file(path, &bytes)) throw ScanFileError(path + ": cannot open: " + std::strerror(errno));
  return parse_scan_bytes(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), path);
}

ScanData parse_scan_bytes(const uint8_t* bytes, size_t size, const std::string& path) {
  ScanData data;
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
      } else if (tag == digitizer_ScanRecord_crc32_tag && wire_type == PB_WT_32BIT) {
        if (!pb_decode_fixed32(&inner, &stored_crc)) throw ScanFileError(where + ": damaged record");
        has_crc = true;
      } else if (!pb_skip_field(&inner, wire_type)) {
        throw ScanFileError(where + ": damaged record");
      }
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
    take(&data, message, where);
    ++data.records;
    offset += header + static_cast<size_t>(length);
    data.complete_bytes = offset;
  }
  return data;
}

}  // namespace dg::host
