// Decimal fields from outside files: the grammar accepted, what is refused, and exact values.
#include <CppUTest/TestHarness.h>

#include <cmath>
#include <string>

#include "host/io/text_field.h"

using namespace dg::host;

TEST_GROUP(TextField){};

TEST(TextField, ReadsSignsPointsExponentsAndBlanksAround) {
  double v = 0;
  CHECK(parse_decimal("+1.5", &v));
  DOUBLES_EQUAL(1.5, v, 0);
  CHECK(parse_decimal("-0.25", &v));
  DOUBLES_EQUAL(-0.25, v, 0);
  CHECK(parse_decimal("1.", &v));
  DOUBLES_EQUAL(1.0, v, 0);
  CHECK(parse_decimal(".5", &v));
  DOUBLES_EQUAL(0.5, v, 0);
  CHECK(parse_decimal(" \t2.5e+3\r", &v));
  DOUBLES_EQUAL(2500.0, v, 0);
  CHECK(parse_decimal("-1E-2", &v));
  DOUBLES_EQUAL(-0.01, v, 0);
  // The nearest double, as strtod gives it: 0.1 is not exact, and both sides round it alike.
  CHECK(parse_decimal("0.1", &v));
  CHECK(v == 0.1);
  CHECK(parse_decimal("12.3456789012345678", &v));
  CHECK(v == 12.3456789012345678);
}

TEST(TextField, KeepsATinyNumberAndRefusesOneTooLarge) {
  double v = 1;
  CHECK(parse_decimal("1e-320", &v));  // a denormal
  CHECK(v > 0 && v < 1e-300);
  CHECK(parse_decimal("1e-400", &v));  // rounds to 0
  DOUBLES_EQUAL(0.0, v, 0);
  v = 7;
  CHECK_FALSE(parse_decimal("1e400", &v));
  CHECK_FALSE(parse_decimal("-1e400", &v));
  DOUBLES_EQUAL(7.0, v, 0);  // untouched on failure
}

TEST(TextField, RefusesWhatIsNotADecimalNumber) {
  double v = 0;
  for (const char* bad : {"", " ", "+", "-", ".", "1e", "1e+", "--1", "+-1", "0x10", "inf", "nan", "-inf", "1,5",
                          "1.5.2", "1 2", "e5", "1d", "\xef\xbc\x91"}) {
    CHECK_FALSE_TEXT(parse_decimal(bad, &v), bad);
  }
  CHECK_FALSE(parse_decimal(std::string("1\0", 2), &v));  // an embedded NUL
}

TEST(TextField, QuotesShortAndSafe) {
  STRCMP_EQUAL("'a\\x1b[2Jb'", quoted(std::string("a\x1b[2Jb")).c_str());
  const std::string long_field(100, 'x');
  STRCMP_EQUAL(("'" + std::string(80, 'x') + "' (cut; 100 characters)").c_str(), quoted(long_field).c_str());
}
