// Fuzzes everything the firmware reads from a host: arbitrary bytes on the simulated board's link
// reach the frame decoder, the reliable link, the message decoder and every request handler
// (scans, commands, resume, acknowledgements), with time passing between chunks.
#include <deque>

#include "firmware/core/device.h"
#include "hw/sim/sim_board.h"

namespace {

class FuzzLink final : public dg::hal::LinkPort {
 public:
  size_t write(const uint8_t*, size_t size) override { return size; }
  size_t read(uint8_t* data, size_t capacity) override {
    size_t n = 0;
    while (n < capacity && n < 48 && !bytes.empty()) {
      data[n++] = bytes.front();
      bytes.pop_front();
    }
    return n;
  }
  bool wait_readable(int) override { return !bytes.empty(); }
  bool closed() const override { return false; }
  std::deque<uint8_t> bytes;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzLink link;
  link.bytes.assign(data, data + size);
  dg::sim::SimConfig sim;
  sim.part.kind = dg::sim::PartKind::kDome;
  dg::sim::SimBoard board(sim, &link);
  dg::DeviceConfig config;
  config.motion.nm_per_step = 2500;
  config.capabilities = digitizer_Capability_CAP_RESUME | digitizer_Capability_CAP_DEVICE_FIT;
  config.gauge.first_clock_timeout_us = 200000;
  dg::Device device(board, config);
  device.begin();
  // Bounded: a scan the bytes start may run long; a few thousand rounds cover its first points.
  for (int round = 0; round < 4000; ++round) {
    device.poll();
    if (!board.wait(device.next_deadline_us()) && link.bytes.empty()) break;
  }
  return 0;
}
