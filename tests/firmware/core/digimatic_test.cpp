// Digimatic frame decoding: the datasheet's examples, and every invalid field refused.
#include "firmware/core/digimatic.h"

#include <CppUTest/TestHarness.h>

namespace {

dg::DigimaticBits frame(const uint8_t (&digits)[13]) {
  dg::DigimaticBits bits;
  for (int i = 0; i < 13; ++i) bits.digit[i] = digits[i];
  return bits;
}

}  // namespace

TEST_GROUP(Digimatic){};

TEST(Digimatic, DecodesTheManualsNegativeExample) {
  // F F F F 8 0 1 2 3 4 5 3 0 -> -12.345 mm (Mitutoyo manual 99MBA043A, 6-12).
  dg::DigimaticReading r;
  CHECK(dg::digimatic_decode(frame({15, 15, 15, 15, 8, 0, 1, 2, 3, 4, 5, 3, 0}), &r) == dg::Status::kOk);
  LONGS_EQUAL(-12345, r.value);
  LONGS_EQUAL(3, r.decimals);
  CHECK(r.unit == dg::GaugeUnit::kMillimetre);
  CHECK(dg::digimatic_to_nm(r) == -12345000);
}

TEST(Digimatic, DecodesFourDecimalsAndInches) {
  dg::DigimaticReading r;
  // +21.0765 mm (manual 99MBC095A example).
  CHECK(dg::digimatic_decode(frame({15, 15, 15, 15, 0, 2, 1, 0, 7, 6, 5, 4, 0}), &r) == dg::Status::kOk);
  CHECK(dg::digimatic_to_nm(r) == 21076500);
  // +0.12345 inch = 3.135630 mm.
  CHECK(dg::digimatic_decode(frame({15, 15, 15, 15, 0, 0, 1, 2, 3, 4, 5, 5, 1}), &r) == dg::Status::kOk);
  CHECK(r.unit == dg::GaugeUnit::kInch);
  CHECK(dg::digimatic_to_nm(r) == 3135630);
}

TEST(Digimatic, RejectsEveryInvalidField) {
  const uint8_t good[13] = {15, 15, 15, 15, 0, 0, 0, 1, 2, 3, 4, 3, 0};
  dg::DigimaticReading r;
  CHECK(dg::digimatic_decode(frame(good), &r) == dg::Status::kOk);
  struct Case {
    int digit;
    uint8_t value;
  } bad[] = {{0, 14}, {3, 0}, {4, 1}, {4, 9}, {5, 10}, {10, 15}, {11, 6}, {12, 8}};
  for (const Case& c : bad) {
    uint8_t digits[13];
    for (int i = 0; i < 13; ++i) digits[i] = good[i];
    digits[c.digit] = c.value;
    CHECK(dg::digimatic_decode(frame(digits), &r) == dg::Status::kBadEncoding);
  }
}

TEST(Digimatic, EncodeRoundTripsAndRefusesTooManyDigits) {
  for (int32_t v : {0, 1, -1, 999999, -999999, 123456}) {
    for (uint8_t d = 0; d <= 5; ++d) {
      dg::DigimaticReading in;
      in.value = v;
      in.decimals = d;
      dg::DigimaticBits bits;
      CHECK(dg::digimatic_encode(in, &bits) == dg::Status::kOk);
      dg::DigimaticReading out;
      CHECK(dg::digimatic_decode(bits, &out) == dg::Status::kOk);
      LONGS_EQUAL(v, out.value);
      LONGS_EQUAL(d, out.decimals);
    }
  }
  dg::DigimaticReading big;
  big.value = 1000000;
  dg::DigimaticBits bits;
  CHECK(dg::digimatic_encode(big, &bits) == dg::Status::kInvalidArgument);
}
