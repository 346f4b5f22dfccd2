// The clock tree: the 25 MHz crystal through the PLL to 96 MHz for the core and 48 MHz for USB.
#pragma once

namespace dg::stm32 {

// Returns false when the crystal did not start and the PLL runs from the internal 16 MHz
// oscillator instead (the same frequencies, but only about 1 % accurate: USB may not enumerate).
bool configure_clocks();

}  // namespace dg::stm32
