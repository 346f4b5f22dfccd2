// Frame encoding and the resynchronising frame decoder.
#include "common/link/frame.h"

#include <cstring>

#include "common/link/crc32.h"

namespace dg {
namespace {

void put_u16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
}
void put_u32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
uint16_t get_u16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
uint32_t get_u32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
         (static_cast<uint32_t>(p[2]) << 16) | (static_cast<uint32_t>(p[3]) << 24);
}

}  // namespace

Status frame_encode(const FrameHeader& header, const uint8_t* payload, size_t payload_size,
                    uint8_t* out, size_t out_capacity, size_t* out_size) {
  if (payload_size > kFrameMaxPayload) return Status::kBadLength;
  // Header, payload and CRC are stuffed piece by piece: a copy of the whole frame took 558 bytes
  // of a device's stack at its deepest call.
  uint8_t head[kFrameHeaderSize];
  head[0] = static_cast<uint8_t>((kFrameVersion << 4) | (static_cast<uint8_t>(header.kind) & 0x0F));
  put_u16(head + 1, header.seq);
  put_u16(head + 3, header.ack);
  uint8_t tail[kFrameCrcSize];
  put_u32(tail, crc32_update(crc32(head, sizeof(head)), payload, payload_size));
  const size_t raw_size = kFrameHeaderSize + payload_size + kFrameCrcSize;
  if (out_capacity < cobs_max_encoded_size(raw_size) + 2) return Status::kOverflow;
  out[0] = 0;
  CobsWriter writer(out + 1, out_capacity - 2);
  writer.put(head, sizeof(head));
  if (payload_size > 0) writer.put(payload, payload_size);
  writer.put(tail, sizeof(tail));
  size_t stuffed = 0;
  const Status status = writer.finish(&stuffed);
  if (status != Status::kOk) return status;
  out[1 + stuffed] = 0;
  *out_size = stuffed + 2;
  return Status::kOk;
}

void FrameReader::reset() {
  fill_ = 0;
  discarding_ = false;
  header_ = FrameHeader{};
  payload_size_ = 0;
  counters_ = Counters{};
}

Status FrameReader::feed(const uint8_t* data, size_t size, size_t* consumed) {
  for (size_t i = 0; i < size; ++i) {
    const uint8_t byte = data[i];
    if (byte != 0) {
      if (discarding_) {
        ++counters_.garbage_bytes;
        continue;
      }
      if (fill_ == capacity_) {
        ++counters_.overflow;
        counters_.garbage_bytes += static_cast<uint32_t>(fill_ + 1);
        fill_ = 0;
        discarding_ = true;
        continue;
      }
      buffer_[fill_++] = byte;
      continue;
    }
    // Delimiter: a frame (or a run of garbage) ends here.
    *consumed = i + 1;
    if (discarding_) {
      discarding_ = false;
      return Status::kOverflow;
    }
    if (fill_ == 0) continue;  // back-to-back delimiters are idle filler
    const Status status = finish_frame();
    fill_ = 0;
    return status;
  }
  *consumed = size;
  return Status::kNeedMore;
}

Status FrameReader::finish_frame() {
  size_t raw_size = 0;
  if (cobs_decode(buffer_, fill_, buffer_, capacity_, &raw_size) != Status::kOk ||
      raw_size < kFrameHeaderSize + kFrameCrcSize || (buffer_[0] >> 4) != kFrameVersion) {
    ++counters_.bad_encoding;
    counters_.garbage_bytes += static_cast<uint32_t>(fill_);
    return Status::kBadEncoding;
  }
  const size_t body = raw_size - kFrameCrcSize;
  if (crc32(buffer_, body) != get_u32(buffer_ + body)) {
    ++counters_.bad_crc;
    return Status::kBadCrc;
  }
  const uint8_t kind = buffer_[0] & 0x0F;
  if (kind > static_cast<uint8_t>(FrameKind::kSync)) {
    ++counters_.bad_encoding;
    return Status::kBadEncoding;
  }
  header_.kind = static_cast<FrameKind>(kind);
  header_.seq = get_u16(buffer_ + 1);
  header_.ack = get_u16(buffer_ + 3);
  payload_size_ = body - kFrameHeaderSize;
  ++counters_.frames;
  return Status::kOk;
}

}  // namespace dg
