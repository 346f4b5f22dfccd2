// Fuzzes the frame decoder: any byte stream, fed in arbitrary chunks, must never crash,
// and every accepted frame must re-encode to a frame that decodes to the same payload.
#include <cstring>
#include <vector>

#include "common/link/frame.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dg::FrameDecoder decoder;
  size_t offset = 0;
  size_t chunk = size > 0 ? (data[0] % 17) + 1 : 1;
  while (offset < size) {
    const size_t n = (size - offset) < chunk ? size - offset : chunk;
    size_t used = 0;
    if (decoder.feed(data + offset, n, &used) == dg::Status::kOk) {
      std::vector<uint8_t> payload(decoder.payload(), decoder.payload() + decoder.payload_size());
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
  return 0;
}
