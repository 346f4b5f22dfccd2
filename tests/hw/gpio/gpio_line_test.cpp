// How a pin map names a GPIO line: CHIP:OFFSET or a line name, optionally active low.
#include <CppUTest/TestHarness.h>

#include <string>

#include "hw/gpio/gpio_line.h"

using dg::gpio::LineSpec;
using dg::gpio::parse_line_spec;

TEST_GROUP(LineSpec) {
  LineSpec spec;
  std::string error;
};

TEST(LineSpec, ChipAndOffset) {
  CHECK(parse_line_spec("gpiochip0:17", &spec, &error));
  STRCMP_EQUAL("gpiochip0", spec.chip.c_str());
  UNSIGNED_LONGS_EQUAL(17, spec.offset);
  CHECK_FALSE(spec.active_low);
  STRCMP_EQUAL("gpiochip0:17", dg::gpio::describe(spec).c_str());
}

TEST(LineSpec, AChipPathMayHoldColonsOnlyBeforeTheOffset) {
  CHECK(parse_line_spec("/dev/gpiochip1:3/active-low", &spec, &error));
  STRCMP_EQUAL("/dev/gpiochip1", spec.chip.c_str());
  UNSIGNED_LONGS_EQUAL(3, spec.offset);
  CHECK(spec.active_low);
}

TEST(LineSpec, ALineName) {
  CHECK(parse_line_spec("GPIO5/active-low", &spec, &error));
  CHECK(spec.chip.empty());
  STRCMP_EQUAL("GPIO5", spec.name.c_str());
  CHECK(spec.active_low);
  STRCMP_EQUAL("GPIO5/active-low", dg::gpio::describe(spec).c_str());
}

TEST(LineSpec, RejectsWhatIsNeitherAndSaysWhy) {
  for (const char* bad : {"", "/active-low", "gpiochip0:", ":4", "gpiochip0:x", "gpiochip0:-1", "gpiochip0:99999"}) {
    error.clear();
    CHECK_FALSE(parse_line_spec(bad, &spec, &error));
    CHECK_FALSE(error.empty());
  }
}
