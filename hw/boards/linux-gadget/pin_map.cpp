// The reference wiring uses BCM line names, which the Raspberry Pi's GPIO driver gives its lines,
// so the map holds whatever chip they are on.
#include "hw/boards/linux-gadget/pin_map.h"

namespace dg::gadget {

namespace {

int index(hal::Pin pin) { return static_cast<int>(pin); }

struct PinName {
  const char* key;
  hal::Pin pin;
};
constexpr PinName kPinNames[] = {
    {"step_x", hal::Pin::kStepX},        {"dir_x", hal::Pin::kDirX},         {"step_y", hal::Pin::kStepY},
    {"dir_y", hal::Pin::kDirY},          {"req", hal::Pin::kGaugeReq},       {"ck", hal::Pin::kGaugeClock},
    {"data", hal::Pin::kGaugeData},      {"limit_x", hal::Pin::kLimitXMin},  {"limit_y", hal::Pin::kLimitYMin},
    {"estop", hal::Pin::kEstop},         {"touch", hal::Pin::kTouchProbe},
};
constexpr int kEnableKey = -1;

}  // namespace

PinMap raspberry_pi_pins() {
  PinMap map;
  const char* names[kPinCount] = {};
  names[index(hal::Pin::kStepX)] = "GPIO17";
  names[index(hal::Pin::kDirX)] = "GPIO27";
  names[index(hal::Pin::kStepY)] = "GPIO22";
  names[index(hal::Pin::kDirY)] = "GPIO23";
  names[index(hal::Pin::kGaugeReq)] = "GPIO5";
  names[index(hal::Pin::kGaugeClock)] = "GPIO6";
  names[index(hal::Pin::kGaugeData)] = "GPIO13";
  names[index(hal::Pin::kLimitXMin)] = "GPIO19";
  names[index(hal::Pin::kLimitYMin)] = "GPIO26";
  names[index(hal::Pin::kEstop)] = "GPIO16";
  names[index(hal::Pin::kTouchProbe)] = "GPIO20";
  for (int pin = 0; pin < kPinCount; ++pin) {
    map.pins[pin].name = names[pin];
    map.wired[pin] = true;
  }
  map.driver_enable.name = "GPIO24";
  map.driver_enable.active_low = true;  // the drivers' EN input is active low
  map.enable_wired = true;
  return map;
}

bool pin_key(const std::string& key, int* pin) {
  if (key == "enable") {
    *pin = kEnableKey;
    return true;
  }
  for (const PinName& name : kPinNames) {
    if (key == name.key) {
      *pin = index(name.pin);
      return true;
    }
  }
  return false;
}

bool apply_pin(const std::string& pair, PinMap* map, std::string* error) {
  const size_t equals = pair.find('=');
  int pin = 0;
  if (equals == std::string::npos || !pin_key(pair.substr(0, equals), &pin)) {
    *error = "'" + pair + "': expected KEY=LINE with KEY one of step_x dir_x step_y dir_y req ck data limit_x "
             "limit_y estop touch enable";
    return false;
  }
  const std::string value = pair.substr(equals + 1);
  const bool none = value == "none";  // not wired: reads inactive, writes go nowhere
  gpio::LineSpec spec;
  if (!none && !gpio::parse_line_spec(value, &spec, error)) return false;
  if (pin == kEnableKey) {
    map->driver_enable = spec;
    map->enable_wired = !none;
  } else {
    map->pins[pin] = spec;
    map->wired[pin] = !none;
  }
  return true;
}

}  // namespace dg::gadget
