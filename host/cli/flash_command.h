// `digitizer flash`: writes a packaged board image to the STM32F411 over USB DFU or an ST-LINK.
#pragma once
#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace dg::host {

struct FlashArgs {
  std::string gauge = "digimatic";  // which packaged image: digimatic or caliper
  std::string image;                // an image file instead of a packaged one
  bool stlink = false;              // through an ST-LINK (openocd) instead of the ROM bootloader's DFU
  bool dry_run = false;             // print the image and the command, run nothing
};

// "" when `bytes` can be an STM32F411 image to write at 0x08000000 (at most 512 KB of flash; its
// vector table's first word a stack pointer in the 128 KB of SRAM, its second a Thumb reset
// address inside that flash); else why not.
std::string stm32f411_image_problem(const std::vector<uint8_t>& bytes);

// The packaged image for `gauge`: $DIGITIZER_FIRMWARE_DIR, else share/digitizer/firmware beside
// this program's prefix (/usr/share/... for /usr/bin/digitizer); "" when there is none.
std::string packaged_image(const std::string& gauge);

void add_flash_command(CLI::App& app, FlashArgs& args);

// Runs `flash` when it was chosen (its exit code); -1 when another command was.
int run_flash_command(const CLI::App& app, const FlashArgs& args);

}  // namespace dg::host
