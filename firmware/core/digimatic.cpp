// Digimatic frame validation and conversion to nanometres.
#include "firmware/core/digimatic.h"

namespace dg {

Status digimatic_decode(const DigimaticBits& bits, DigimaticReading* reading) {
  for (int i = 0; i < 4; ++i) {
    if (bits.digit[i] != 0xF) return Status::kBadEncoding;
  }
  const uint8_t sign = bits.digit[4];
  if (sign != 0 && sign != 8) return Status::kBadEncoding;
  int32_t value = 0;
  for (int i = 5; i < 11; ++i) {
    if (bits.digit[i] > 9) return Status::kBadEncoding;
    value = value * 10 + bits.digit[i];
  }
  const uint8_t decimals = bits.digit[11];
  if (decimals > 5) return Status::kBadEncoding;
  const uint8_t unit = bits.digit[12];
  if (unit > 7) return Status::kBadEncoding;
  reading->value = sign == 8 ? -value : value;
  reading->decimals = decimals;
  // 0 mm, 1 inch, 2-4 mm with judgement, 5-7 inch with judgement.
  reading->unit = (unit == 1 || unit >= 5) ? GaugeUnit::kInch : GaugeUnit::kMillimetre;
  return Status::kOk;
}

Status digimatic_encode(const DigimaticReading& reading, DigimaticBits* bits) {
  if (reading.decimals > 5 || reading.value > 999999 || reading.value < -999999) {
    return Status::kInvalidArgument;
  }
  *bits = DigimaticBits{};
  for (int i = 0; i < 4; ++i) bits->digit[i] = 0xF;
  bits->digit[4] = reading.value < 0 ? 8 : 0;
  int32_t magnitude = reading.value < 0 ? -reading.value : reading.value;
  for (int i = 10; i >= 5; --i) {
    bits->digit[i] = static_cast<uint8_t>(magnitude % 10);
    magnitude /= 10;
  }
  bits->digit[11] = reading.decimals;
  bits->digit[12] = reading.unit == GaugeUnit::kInch ? 1 : 0;
  return Status::kOk;
}

int64_t digimatic_to_nm(const DigimaticReading& reading) {
  int64_t scale = 1;
  for (int i = reading.decimals; i < 5; ++i) scale *= 10;
  // mm: value * 10^(6-d) nm = value * 10 * 10^(5-d); inch: value * 254 * 10^(5-d).
  const int64_t per_unit = reading.unit == GaugeUnit::kInch ? 254 : 10;
  return static_cast<int64_t>(reading.value) * per_unit * scale;
}

}  // namespace dg
