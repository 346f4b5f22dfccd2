// Fuzzes everything the host reads from a device: the input becomes the device's byte stream to a
// Session saying hello and then capturing a whole scan into memory. Frames are built from the input
// with good CRCs and numbered from the session the host opened, so they get past the frame decoder
// into the reliable link, the message decoder and the capture's handling of every message; raw
// bytes between them exercise resynchronisation.
//
// The input is a run of records. A first byte with the top bit set is raw: its low 6 bits say how
// many bytes follow, copied to the wire as they are. Otherwise it is a frame: kind (low 2 bits;
// 3 is data too), then seq and ack as 16-bit little-endian offsets from the session's id, a 16-bit
// payload length (cut to the bytes left and to a frame's payload), and the payload (an Envelope).
#include <algorithm>
#include <deque>
#include <exception>
#include <string>

#include "common/link/frame.h"
#include "host/device/capture.h"
#include "host/device/session.h"
#include "host/scan/scan_sink.h"
#include "host/transport/transport.h"
#include "tests/support/scan_request.h"

namespace {

class FuzzDeviceTransport final : public dg::host::Transport {
 public:
  FuzzDeviceTransport(const uint8_t* data, size_t size) : input_(data), size_(size) {}

  // Listens to the host only for the session id its sync frame carries.
  void write(const uint8_t* data, size_t size) override {
    size_t offset = 0;
    while (offset < size) {
      size_t used = 0;
      const dg::Status status = host_frames_.feed(data + offset, size - offset, &used);
      offset += used;
      if (status == dg::Status::kOk && host_frames_.header().kind == dg::FrameKind::kSync) {
        session_ = host_frames_.header().ack;
      }
    }
  }

  size_t read(uint8_t* data, size_t capacity, int) override {
    if (wire_.empty()) next_record();
    // The end of the input is a pulled cable: the capture ends at once instead of timing out.
    if (wire_.empty()) throw dg::host::TransportError("fuzz: end of the device's bytes");
    const size_t n = std::min({capacity, wire_.size(), static_cast<size_t>(64)});
    std::copy(wire_.begin(), wire_.begin() + static_cast<std::ptrdiff_t>(n), data);
    wire_.erase(wire_.begin(), wire_.begin() + static_cast<std::ptrdiff_t>(n));
    return n;
  }

  std::string describe() const override { return "fuzz:"; }

 private:
  uint16_t take16() {
    uint16_t v = 0;
    for (int i = 0; i < 2 && offset_ < size_; ++i) v = static_cast<uint16_t>(v | input_[offset_++] << (8 * i));
    return v;
  }

  void next_record() {
    if (offset_ >= size_) return;
    const uint8_t first = input_[offset_++];
    if (first & 0x80) {
      const size_t n = std::min(static_cast<size_t>(first & 0x3f), size_ - offset_);
      wire_.insert(wire_.end(), input_ + offset_, input_ + offset_ + n);
      offset_ += n;
      return;
    }
    dg::FrameHeader header;
    const uint8_t kind = first & 3;
    header.kind = kind == 1 ? dg::FrameKind::kAckOnly : kind == 2 ? dg::FrameKind::kSync : dg::FrameKind::kData;
    header.seq = static_cast<uint16_t>(session_ + take16());
    header.ack = static_cast<uint16_t>(session_ + take16());
    const size_t length = std::min({static_cast<size_t>(take16()), size_ - offset_, dg::kFrameMaxPayload});
    uint8_t frame[dg::kFrameMaxWire];
    size_t frame_size = 0;
    if (dg::frame_encode(header, input_ + offset_, length, frame, sizeof(frame), &frame_size) == dg::Status::kOk) {
      wire_.insert(wire_.end(), frame, frame + frame_size);
    }
    offset_ += length;
  }

  const uint8_t* input_;
  size_t size_;
  size_t offset_ = 0;
  uint16_t session_ = 0;
  dg::FrameDecoder host_frames_;
  std::deque<uint8_t> wire_;
};

// Keeps nothing: the capture's checks run on what it is given, not on a file.
class NullSink final : public dg::host::ScanSink {
 public:
  void append(const digitizer_Envelope&) override { ++records; }
  void sync() override {}
  const std::string& path() const override { return path_; }
  size_t records = 0;

 private:
  std::string path_ = "fuzz.scan";
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzDeviceTransport transport(data, size);
  dg::host::Session session(transport);
  try {
    const digitizer_Hello hello = session.hello(2000);
    NullSink sink;
    dg::host::CaptureOptions options;
    options.reconnect_timeout_ms = 0;
    const digitizer_ScanRequest request =
        dg::test::grid_request(7, 0, 4000000, 3000000, 1000000, digitizer_ScanPattern_PATTERN_SERPENTINE);
    dg::host::capture_scan(session, hello, request, sink, options);
  } catch (const std::exception&) {
    // Refusals, a device that breaks the protocol, the end of the input: all said by exceptions.
  }
  return 0;
}
