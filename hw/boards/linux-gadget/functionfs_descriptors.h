// The blobs a FunctionFS driver writes to ep0 before its endpoints exist: the vendor interface and
// its two bulk endpoints (the same ones hw/usb gives the STM32 board) at full and high speed, and
// the interface's name. Layouts: linux/usb/functionfs.h (descriptors v2, strings).
#pragma once
#include <cstdint>
#include <vector>

namespace dg::gadget {

std::vector<uint8_t> functionfs_descriptors();
std::vector<uint8_t> functionfs_strings();

}  // namespace dg::gadget
