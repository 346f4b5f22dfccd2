// flash checks an image's vector table before anything touches the board.
#include "host/cli/flash_command.h"

#include <CppUTest/TestHarness.h>

#include <vector>

using dg::host::stm32f411_image_problem;

namespace {

std::vector<uint8_t> image(uint32_t stack, uint32_t reset, size_t size = 1024) {
  std::vector<uint8_t> b(size, 0xFF);
  for (int i = 0; i < 4; ++i) {
    b[i] = static_cast<uint8_t>(stack >> (8 * i));
    b[4 + i] = static_cast<uint8_t>(reset >> (8 * i));
  }
  return b;
}

}  // namespace

TEST_GROUP(FlashImage){};

TEST(FlashImage, AVectorTableWithStackInSramAndThumbResetInTheImageIsAccepted) {
  STRCMP_EQUAL("", stm32f411_image_problem(image(0x20003F68, 0x08000301)).c_str());
  STRCMP_EQUAL("", stm32f411_image_problem(image(0x20020000, 0x08000101)).c_str());
}

TEST(FlashImage, AnElfFileIsRefusedAsNoImageForTheChip) {
  const std::vector<uint8_t> elf = image(0x464C457F, 0x00010101);
  STRCMP_CONTAINS("no initial stack pointer in SRAM", stm32f411_image_problem(elf).c_str());
}

TEST(FlashImage, AResetVectorOutsideTheImageOrWithoutTheThumbBitIsRefused) {
  STRCMP_CONTAINS("reset vector", stm32f411_image_problem(image(0x20004000, 0x08000300)).c_str());
  STRCMP_CONTAINS("reset vector", stm32f411_image_problem(image(0x20004000, 0x08010001, 1024)).c_str());
}

TEST(FlashImage, AnImageTooShortOrLargerThanTheFlashIsRefused) {
  STRCMP_CONTAINS("shorter than a vector table", stm32f411_image_problem(std::vector<uint8_t>(6, 0)).c_str());
  STRCMP_CONTAINS("more than the 512 KB", stm32f411_image_problem(image(0x20004000, 0x08000101, 512 * 1024 + 4)).c_str());
}
