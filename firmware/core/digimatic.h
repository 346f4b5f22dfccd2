// Mitutoyo Digimatic frame: 13 four-bit digits, each sent least significant bit first.
// d1-d4 = 0xF, d5 = sign (0 plus, 8 minus), d6-d11 = six BCD digits (most significant
// first), d12 = decimal point position (digits after the point, 0-5), d13 = unit
// (0 mm, 1 inch; 2-7 add a tolerance judgement). Per the Mitutoyo Digimatic output
// specification as printed in Mitutoyo instrument manuals (e.g. No. 99MBA043A, 6-12).
#pragma once
#include <cstdint>

#include "common/status.h"

namespace dg {

constexpr int kDigimaticDigits = 13;
constexpr int kDigimaticBits = kDigimaticDigits * 4;

enum class GaugeUnit : uint8_t { kMillimetre, kInch };

struct DigimaticReading {
  int32_t value = 0;      // signed, in units of 10^-decimals of `unit`
  uint8_t decimals = 0;   // 0..5
  GaugeUnit unit = GaugeUnit::kMillimetre;
};

// Bits in the order they came off the wire (bit i of the frame is bit i%4 of digit i/4).
struct DigimaticBits {
  uint8_t digit[kDigimaticDigits] = {};
  void set_bit(int index, bool level) {
    if (level) digit[index / 4] = static_cast<uint8_t>(digit[index / 4] | (1u << (index % 4)));
  }
};

// Validates every field; kBadEncoding for any frame that is not a Digimatic reading,
// so a shifted or damaged frame is an error and never a wrong number.
Status digimatic_decode(const DigimaticBits& bits, DigimaticReading* reading);

// The inverse, for gauges and tests: kInvalidArgument if the value needs more than
// six digits or decimals > 5.
Status digimatic_encode(const DigimaticReading& reading, DigimaticBits* bits);

// Converts a reading to integer nanometres (exact: 1 inch = 25.4 mm).
int64_t digimatic_to_nm(const DigimaticReading& reading);

}  // namespace dg
