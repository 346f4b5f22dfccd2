// Link frames: header + payload + CRC-32, COBS-stuffed between two 0x00 delimiters.
//
// Before stuffing a frame is
//   [0]    version (high nibble, kFrameVersion) | kind (low nibble, FrameKind)
//   [1..2] seq, little endian: numbers every data frame of one direction
//   [3..4] ack, little endian: the last seq this side received in order
//   [5..]  payload (one encoded Envelope)
//   [n-4..n-1] CRC-32 of bytes [0, n-4), little endian
// seq and ack let the reliable link (retransmission, duplicates, windows) live
// on this same frame. A frame starts and ends with 0x00, so garbage before it is
// cut off at its first byte and a reader resynchronises on the very next frame.
#pragma once
#include <cstddef>
#include <cstdint>

#include "common/link/cobs.h"
#include "common/status.h"

namespace dg {

constexpr uint8_t kFrameVersion = 1;
constexpr size_t kFrameHeaderSize = 5;
constexpr size_t kFrameCrcSize = 4;
constexpr size_t kFrameMaxPayload = 544;  // >= digitizer_Envelope_size (checked in messages.cpp)
constexpr size_t kFrameMaxRaw = kFrameHeaderSize + kFrameMaxPayload + kFrameCrcSize;
// Stuffed bytes plus the two delimiters.
constexpr size_t kFrameMaxWire = cobs_max_encoded_size(kFrameMaxRaw) + 2;

enum class FrameKind : uint8_t {
  kData = 0,     // carries a payload
  kAckOnly = 1,  // no payload, only the ack field matters
  kSync = 2,     // the first data frame of a session; its ack field holds the session's id
};

struct FrameHeader {
  FrameKind kind = FrameKind::kData;
  uint16_t seq = 0;
  uint16_t ack = 0;
};

// Builds a complete wire frame (delimiter, stuffed bytes, delimiter) into `out`.
Status frame_encode(const FrameHeader& header, const uint8_t* payload, size_t payload_size,
                    uint8_t* out, size_t out_capacity, size_t* out_size);

// Incremental frame reader over a buffer it does not own (SizedFrameDecoder holds one). Feed bytes
// as they arrive; each call reports at most one finished frame. Bad frames are counted and
// skipped, never returned.
class FrameReader {
 public:
  struct Counters {
    uint32_t frames = 0;
    uint32_t bad_crc = 0;
    uint32_t bad_encoding = 0;  // COBS errors, short frames, wrong version
    uint32_t overflow = 0;      // more bytes than a frame can hold before a delimiter
    uint32_t garbage_bytes = 0; // bytes thrown away while resynchronising
  };

  // It points into its owner: a copy would read into the original's buffer.
  FrameReader(const FrameReader&) = delete;
  FrameReader& operator=(const FrameReader&) = delete;

  // Consumes bytes from `data` up to and including the delimiter that ends a
  // frame. Returns kOk with *consumed set when a valid frame is ready (read it
  // with header()/payload()), kNeedMore when all bytes were used without
  // completing a frame, or an error status for a rejected frame (also with
  // *consumed set, so the caller just keeps feeding).
  Status feed(const uint8_t* data, size_t size, size_t* consumed);

  const FrameHeader& header() const { return header_; }
  const uint8_t* payload() const { return buffer_ + kFrameHeaderSize; }
  size_t payload_size() const { return payload_size_; }
  const Counters& counters() const { return counters_; }
  // Forgets a partial frame and the counters, as a new reader would.
  void reset();

 protected:
  FrameReader(uint8_t* buffer, size_t capacity) : buffer_(buffer), capacity_(capacity) {}
  ~FrameReader() = default;

 private:
  Status finish_frame();

  uint8_t* buffer_;
  size_t capacity_;
  size_t fill_ = 0;
  bool discarding_ = false;  // overflowed: skip until the next delimiter
  FrameHeader header_{};
  size_t payload_size_ = 0;
  Counters counters_{};
};

// A frame reader for payloads of up to kMaxPayload bytes. A device, which only ever receives the
// host's short requests, keeps room for those rather than for the largest message; a longer frame
// is counted as an overflow and skipped.
template <size_t kMaxPayload>
class SizedFrameDecoder : public FrameReader {
 public:
  static_assert(kMaxPayload <= kFrameMaxPayload, "no frame carries more than kFrameMaxPayload");
  SizedFrameDecoder() : FrameReader(storage_, sizeof(storage_)) {}

 private:
  uint8_t storage_[cobs_max_encoded_size(kFrameHeaderSize + kMaxPayload + kFrameCrcSize)] = {};
};

// Room for every frame.
using FrameDecoder = SizedFrameDecoder<kFrameMaxPayload>;

}  // namespace dg
