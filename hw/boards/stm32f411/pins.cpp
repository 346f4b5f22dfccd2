// Switches are normally closed to ground with pull-ups, so a pressed switch and a broken wire both
// read high, asserted (fail safe). The gauge port's REQ drives an NPN transistor that pulls the
// gauge's REQ low; CK and DATA come through a non-inverting level shifter at the gauge's levels.
#include "hw/boards/stm32f411/pins.h"

#include "hw/boards/stm32f411/registers.h"

namespace dg::stm32 {

namespace {

constexpr uint8_t kNone = 0, kPullUp = 1;

// In the order of hal::Pin.
constexpr PinMap kPins[static_cast<int>(hal::Pin::kCount)] = {
    {kGpioB, 6, true, false, kNone},     // kStepX
    {kGpioB, 7, true, false, kNone},     // kDirX
    {kGpioB, 8, true, false, kNone},     // kStepY
    {kGpioB, 9, true, false, kNone},     // kDirY
    {kGpioA, 1, true, false, kNone},     // kGaugeReq: high turns the transistor on, REQ low
    {kGpioA, 2, false, false, kPullUp},  // kGaugeClock (EXTI2)
    {kGpioA, 3, false, false, kPullUp},  // kGaugeData
    // Normally closed to ground: closed reads low; pressed, or a broken wire, reads high (asserted).
    {kGpioB, 12, false, false, kPullUp},  // kLimitXMin
    {kGpioB, 13, false, false, kPullUp},  // kLimitYMin
    {kGpioB, 14, false, false, kPullUp},  // kEstop
    {kGpioB, 15, false, false, kPullUp},  // kTouchProbe (EXTI15): a kinematic probe's contacts open on touch
};

}  // namespace

const PinMap& pin_map(hal::Pin pin) { return kPins[static_cast<int>(pin)]; }

}  // namespace dg::stm32
