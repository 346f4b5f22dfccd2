// COBS encoder and decoder (Cheshire & Baker, "Consistent Overhead Byte Stuffing", 1999).
#include "common/link/cobs.h"

namespace dg {

void CobsWriter::place_code() {
  if (code_index_ < capacity_) {
    out_[code_index_] = code_;
  } else {
    overflow_ = true;
  }
}

void CobsWriter::close_block() {
  place_code();
  code_index_ = write_++;
  code_ = 1;
}

void CobsWriter::put(const uint8_t* in, size_t size) {
  for (size_t i = 0; i < size; ++i) {
    if (in[i] == 0) {
      close_block();
      continue;
    }
    if (write_ < capacity_) {
      out_[write_] = in[i];
    } else {
      overflow_ = true;
    }
    ++write_;
    if (++code_ == 0xFF) close_block();
  }
}

Status CobsWriter::finish(size_t* out_size) {
  place_code();
  if (overflow_) return Status::kOverflow;
  *out_size = write_;
  return Status::kOk;
}

Status cobs_encode(const uint8_t* in, size_t in_size, uint8_t* out, size_t out_capacity,
                   size_t* out_size) {
  if (out_capacity < cobs_max_encoded_size(in_size)) return Status::kOverflow;
  CobsWriter writer(out, out_capacity);
  writer.put(in, in_size);
  return writer.finish(out_size);
}

Status cobs_decode(const uint8_t* in, size_t in_size, uint8_t* out, size_t out_capacity,
                   size_t* out_size) {
  size_t read = 0;
  size_t write = 0;
  while (read < in_size) {
    const uint8_t code = in[read++];
    if (code == 0) return Status::kBadEncoding;
    const size_t run = static_cast<size_t>(code) - 1;
    if (read + run > in_size) return Status::kBadEncoding;
    if (write + run > out_capacity) return Status::kOverflow;
    for (size_t i = 0; i < run; ++i) {
      if (in[read] == 0) return Status::kBadEncoding;
      out[write++] = in[read++];
    }
    // A code below 0xFF stands for a zero byte, except after the last run.
    if (code != 0xFF && read < in_size) {
      if (write >= out_capacity) return Status::kOverflow;
      out[write++] = 0;
    }
  }
  *out_size = write;
  return Status::kOk;
}

}  // namespace dg
