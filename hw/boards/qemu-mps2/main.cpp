// The device firmware on QEMU's mps2-an386 (Cortex-M4): the firmware core on the simulated table
// and gauge (hw/sim, in virtual time inside the image), its link on UART0. scripts/test boots it
// under -icount with UART0 on a unix socket and scans through it with `digitizer scan`.
#include <new>

#include "firmware/core/device.h"
#include "hw/boards/cortex-m/runtime.h"
#include "hw/boards/qemu-mps2/uart_link.h"
#include "hw/sim/sim_device.h"

namespace {

// Static storage built in place: the image registers no destructors and has no heap.
alignas(dg::board::UartLink) unsigned char link_storage[sizeof(dg::board::UartLink)];
alignas(dg::sim::SimBoard) unsigned char board_storage[sizeof(dg::sim::SimBoard)];
alignas(dg::Device) unsigned char device_storage[sizeof(dg::Device)];

}  // namespace

int main() {
  auto* link = new (link_storage) dg::board::UartLink();
  dg::sim::SimConfig sim;
  sim.part.kind = dg::sim::PartKind::kDome;
  auto* board = new (board_storage) dg::sim::SimBoard(sim, link);
  dg::DeviceConfig config = dg::sim::simulated_device(sim);
  config.device_id = "QEMU-0001";
  config.board = "qemu-mps2";
  config.stack_used_bytes = dg::cortex_m::stack_used_bytes;
  config.stack_size_bytes = dg::cortex_m::stack_size_bytes();
  auto* device = new (device_storage) dg::Device(*board, config);
  device->run();
  return 0;
}
