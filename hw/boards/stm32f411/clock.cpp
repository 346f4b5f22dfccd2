// PLL figures (RM0383 6.3.2): VCO input = source / M = 1 MHz, VCO = 1 MHz * N = 192 MHz,
// SYSCLK = VCO / P = 96 MHz, USB = VCO / Q = 48 MHz exactly. 96 MHz needs voltage scale 1 (above
// 84 MHz) and 3 flash wait states at 2.7-3.6 V (RM0383 table 5). APB1 may not exceed 50 MHz: /2.
#include "hw/boards/stm32f411/clock.h"

#include "hw/boards/stm32f411/registers.h"

namespace dg::stm32 {

namespace {

constexpr uint32_t kHseOn = 1u << 16, kHseReady = 1u << 17, kPllOn = 1u << 24, kPllReady = 1u << 25;

bool wait_for(uint32_t address, uint32_t mask, uint32_t value, uint32_t rounds) {
  for (uint32_t i = 0; i < rounds; ++i) {
    if ((reg(address) & mask) == value) return true;
  }
  return false;
}

}  // namespace

bool configure_clocks() {
  reg(kRccApb1Enr) |= 1u << 28;                         // PWREN
  reg(kPwrCr) = (reg(kPwrCr) & ~(3u << 14)) | (3u << 14);  // VOS: scale 1
  reg(kRccCr) |= kHseOn;
  // A crystal starts within a few milliseconds; this is some 50 ms on the 16 MHz reset clock.
  const bool crystal = wait_for(kRccCr, kHseReady, kHseReady, 200000);
  if (!crystal) reg(kRccCr) &= ~kHseOn;
  const uint32_t m = crystal ? 25 : 16;
  const uint32_t source_hse = crystal ? 1u << 22 : 0;
  // M (5:0), N (14:6), P (17:16, 0 = /2), source (22), Q (27:24); the reserved bits keep their
  // reset values, as the manual asks.
  constexpr uint32_t kFields = 0x3Fu | (0x1FFu << 6) | (3u << 16) | (1u << 22) | (0xFu << 24);
  reg(kRccPllCfgr) = (reg(kRccPllCfgr) & ~kFields) | m | (192u << 6) | source_hse | (4u << 24);
  reg(kRccCr) |= kPllOn;
  wait_for(kRccCr, kPllReady, kPllReady, 1000000);
  // Wait states, prefetch, instruction and data caches before the faster clock.
  reg(kFlashAcr) = 3u | (1u << 8) | (1u << 9) | (1u << 10);
  wait_for(kFlashAcr, 0xF, 3, 1000);
  // AHB /1, APB1 /2, APB2 /1, then switch SYSCLK to the PLL.
  reg(kRccCfgr) = (reg(kRccCfgr) & ~((0xFu << 4) | (7u << 10) | (7u << 13) | 3u)) | (4u << 10) | 2u;
  wait_for(kRccCfgr, 3u << 2, 2u << 2, 100000);
  return crystal;
}

}  // namespace dg::stm32
