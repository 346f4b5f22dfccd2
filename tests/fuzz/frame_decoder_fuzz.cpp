// Fuzzes the frame decoder: any byte stream, fed in arbitrary chunks, must never crash,
// and every accepted frame must re-encode to a frame that decodes to the same payload. The
// device's reader, with room for the host's requests only, reads the same stream: it must accept
// exactly the frames of the full reader that fit its room.
#include <cstring>
#include <vector>

#include "common/link/frame.h"
#include "common/proto/messages.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dg::FrameDecoder decoder;
  // The device's reader sees the whole stream at once; its frames are listed to compare.
  dg::SizedFrameDecoder<dg::kHostEnvelopeMaxSize> device;
  std::vector<std::vector<uint8_t>> at_device, fitting;
  for (size_t at = 0; at < size;) {
    size_t used = 0;
    if (device.feed(data + at, size - at, &used) == dg::Status::kOk) {
      at_device.emplace_back(device.payload(), device.payload() + device.payload_size());
    }
    at += used;
  }
  size_t offset = 0;
  size_t chunk = size > 0 ? (data[0] % 17) + 1 : 1;
  while (offset < size) {
    const size_t n = (size - offset) < chunk ? size - offset : chunk;
    size_t used = 0;
    if (decoder.feed(data + offset, n, &used) == dg::Status::kOk) {
      std::vector<uint8_t> payload(decoder.payload(), decoder.payload() + decoder.payload_size());
      if (payload.size() <= dg::kHostEnvelopeMaxSize) fitting.push_back(payload);
      uint8_t wire[dg::kFrameMaxWire];
      size_t wire_size = 0;
      if (dg::frame_encode(decoder.header(), payload.data(), payload.size(), wire, sizeof(wire),
                           &wire_size) != dg::Status::kOk) {
        __builtin_trap();
      }
      dg::FrameDecoder again;
      size_t again_used = 0;
      if (again.feed(wire, wire_size, &again_used) != dg::Status::kOk ||
          again.payload_size() != payload.size() ||
          std::memcmp(again.payload(), payload.data(), payload.size()) != 0) {
        __builtin_trap();
      }
    }
    offset += used;
  }
  if (fitting != at_device) __builtin_trap();
  return 0;
}
