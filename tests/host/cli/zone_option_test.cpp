// inspect --zone: a name, a box and a tolerance, and a clear message for each way to get it wrong.
#include "host/cli/zone_option.h"

#include <CppUTest/TestHarness.h>

#include <stdexcept>
#include <string>

namespace {

std::string refusal(const std::string& text) {
  try {
    dg::host::parse_tolerance_zone(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_GROUP(ZoneOption){};

TEST(ZoneOption, ReadsASymmetricAndAnAsymmetricTolerance) {
  const dg::host::ToleranceZone a = dg::host::parse_tolerance_zone("seal=10:30,5.5:12,0.01");
  STRCMP_EQUAL("seal", a.name.c_str());
  DOUBLES_EQUAL(10, a.x0_mm, 0);
  DOUBLES_EQUAL(30, a.x1_mm, 0);
  DOUBLES_EQUAL(5.5, a.y0_mm, 0);
  DOUBLES_EQUAL(12, a.y1_mm, 0);
  DOUBLES_EQUAL(-0.01, a.limits.lower_mm, 0);
  DOUBLES_EQUAL(0.01, a.limits.upper_mm, 0);
  const dg::host::ToleranceZone b = dg::host::parse_tolerance_zone("boss_2=-5:5,-5:5,-0.02:0.01");
  DOUBLES_EQUAL(-5, b.x0_mm, 0);
  DOUBLES_EQUAL(-0.02, b.limits.lower_mm, 0);
  DOUBLES_EQUAL(0.01, b.limits.upper_mm, 0);
}

TEST(ZoneOption, SaysWhatIsWrong) {
  STRCMP_CONTAINS("give NAME=", refusal("10:30,5:12,0.01").c_str());
  STRCMP_CONTAINS("letters, digits", refusal("se al=10:30,5:12,0.01").c_str());
  STRCMP_CONTAINS("after the name", refusal("seal=10:30,5:12").c_str());
  STRCMP_CONTAINS("after the name", refusal("seal=10:30,5:12,0.01,3").c_str());
  STRCMP_CONTAINS("x range must be MIN:MAX", refusal("seal=10,5:12,0.01").c_str());
  STRCMP_CONTAINS("y range 12:5 must have MIN < MAX", refusal("seal=10:30,12:5,0.01").c_str());
  STRCMP_CONTAINS("x range 'ten' is not a number", refusal("seal=ten:30,5:12,0.01").c_str());
  STRCMP_CONTAINS("tolerance must be > 0", refusal("seal=10:30,5:12,-0.01").c_str());
  STRCMP_CONTAINS("tolerance 'nan' is not a number", refusal("seal=10:30,5:12,nan").c_str());
  STRCMP_CONTAINS("tolerance 0.01:-0.01 must have MIN < MAX", refusal("seal=10:30,5:12,0.01:-0.01").c_str());
}

TEST(ZoneOption, ReadsADatumRegionWithoutATolerance) {
  const dg::host::ToleranceZone d = dg::host::parse_datum_region("A=0:40,0:4");
  STRCMP_EQUAL("A", d.name.c_str());
  DOUBLES_EQUAL(40, d.x1_mm, 0);
  DOUBLES_EQUAL(4, d.y1_mm, 0);
  try {
    dg::host::parse_datum_region("A=0:40,0:4,0.01");
    FAIL("a datum with a tolerance was accepted");
  } catch (const std::invalid_argument& e) {
    STRCMP_CONTAINS("--datum A: give X0:X1,Y0:Y1 after the name", e.what());
  }
}
