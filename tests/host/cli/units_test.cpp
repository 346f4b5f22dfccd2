// Command-line millimetre parsing: exact nanometres, clear refusals.
#include "host/cli/units.h"

#include <CppUTest/TestHarness.h>

#include <stdexcept>

TEST_GROUP(Units){};

TEST(Units, ParsesMillimetresToNanometres) {
  LONGS_EQUAL(12500000, dg::host::parse_mm("12.5", "--x"));
  LONGS_EQUAL(-1, dg::host::parse_mm("-0.000001", "--x"));
  LONGS_EQUAL(1000000, dg::host::parse_mm("1", "--step"));
}

TEST(Units, ParsesRanges) {
  const dg::host::RangeNm r = dg::host::parse_range_mm("-5:40", "--x");
  LONGS_EQUAL(-5000000, r.min_nm);
  LONGS_EQUAL(40000000, r.max_nm);
}

TEST(Units, RefusesBadInput) {
  for (const char* bad : {"", "abc", "1.5mm", "nan", "inf", "1e30"}) {
    CHECK_THROWS(std::invalid_argument, dg::host::parse_mm(bad, "--x"));
  }
  for (const char* bad : {"5", "40:0", ":", "a:b"}) {
    CHECK_THROWS(std::invalid_argument, dg::host::parse_range_mm(bad, "--x"));
  }
}
