// The device firmware on QEMU's mps2-an386 (Cortex-M4): the firmware core on the simulated table
// and gauge (hw/sim, in virtual time inside the image), its link on UART0. scripts/test boots it
// under -icount with UART0 on a unix socket and scans through it with `digitizer scan`.
#include <new>

#include "firmware/core/device.h"
#include "hw/boards/qemu-mps2/uart_link.h"

namespace {

// Static storage built in place: the image registers no destructors and has no heap.
alignas(dg::board::UartLink) unsigned char link_storage[sizeof(dg::board::UartLink)];
alignas(dg::sim::SimBoard) unsigned char board_storage[sizeof(dg::sim::SimBoard)];
alignas(dg::Device) unsigned char device_storage[sizeof(dg::Device)];

}  // namespace

// Virtual destructors bring deleting destructors and with them operator delete; nothing is ever
// allocated, so it frees nothing.
void operator delete(void*) noexcept {}
void operator delete(void*, unsigned int) noexcept {}

int main() {
  auto* link = new (link_storage) dg::board::UartLink();
  dg::sim::SimConfig sim;
  sim.part.kind = dg::sim::PartKind::kDome;
  auto* board = new (board_storage) dg::sim::SimBoard(sim, link);
  dg::DeviceConfig config;
  config.motion.nm_per_step = sim.nm_per_step;
  config.device_id = "QEMU-0001";
  config.board = "qemu-mps2";
  config.firmware_version = DIGITIZER_VERSION;
  config.capabilities = digitizer_Capability_CAP_DIGIMATIC | digitizer_Capability_CAP_DEVICE_FIT |
                        digitizer_Capability_CAP_SIMULATED | digitizer_Capability_CAP_RESUME |
                        digitizer_Capability_CAP_HOMING | digitizer_Capability_CAP_TOUCH_PROBE;
  // As in digitizer-sim: virtual time runs ahead of the host; give the host time to answer.
  config.retransmit_us = 5000000;
  config.host_silence_us = 300000000;
  config.gauge.first_clock_timeout_us = sim.gauge.request_to_clock_us + 100000;
  auto* device = new (device_storage) dg::Device(*board, config);
  device->run();
  return 0;
}
