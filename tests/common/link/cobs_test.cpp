// COBS: no zero bytes after encoding, exact round trips, and rejected bad input.
#include "common/link/cobs.h"

#include <CppUTest/TestHarness.h>

#include <vector>

namespace {

std::vector<uint8_t> round_trip(const std::vector<uint8_t>& in) {
  std::vector<uint8_t> encoded(dg::cobs_max_encoded_size(in.size()));
  size_t encoded_size = 0;
  CHECK(dg::cobs_encode(in.data(), in.size(), encoded.data(), encoded.size(), &encoded_size) ==
        dg::Status::kOk);
  for (size_t i = 0; i < encoded_size; ++i) CHECK(encoded[i] != 0);
  std::vector<uint8_t> decoded(in.size() + 1);
  size_t decoded_size = 0;
  CHECK(dg::cobs_decode(encoded.data(), encoded_size, decoded.data(), decoded.size(),
                        &decoded_size) == dg::Status::kOk);
  decoded.resize(decoded_size);
  return decoded;
}

}  // namespace

TEST_GROUP(Cobs){};

TEST(Cobs, RoundTripsZerosAndLongRuns) {
  std::vector<std::vector<uint8_t>> cases = {{}, {0}, {0, 0}, {1, 0, 2}, {0x11, 0x22, 0x00, 0x33}};
  std::vector<uint8_t> long_run(600);
  for (size_t i = 0; i < long_run.size(); ++i) long_run[i] = static_cast<uint8_t>(i % 255 + 1);
  cases.push_back(long_run);
  std::vector<uint8_t> mixed(1000);
  for (size_t i = 0; i < mixed.size(); ++i) mixed[i] = static_cast<uint8_t>((i * 37) % 7 == 0 ? 0 : i);
  cases.push_back(mixed);
  for (const auto& c : cases) CHECK(round_trip(c) == c);
}

TEST(Cobs, RejectsZeroInsideEncodedData) {
  const uint8_t bad[] = {0x03, 0x11, 0x00};
  uint8_t out[8];
  size_t size = 0;
  CHECK(dg::cobs_decode(bad, sizeof(bad), out, sizeof(out), &size) == dg::Status::kBadEncoding);
}

TEST(Cobs, RejectsARunLongerThanTheInput) {
  const uint8_t bad[] = {0x05, 0x11, 0x22};
  uint8_t out[8];
  size_t size = 0;
  CHECK(dg::cobs_decode(bad, sizeof(bad), out, sizeof(out), &size) == dg::Status::kBadEncoding);
}

TEST(Cobs, ReportsTooSmallOutput) {
  const uint8_t in[] = {1, 2, 3, 4};
  uint8_t out[3];
  size_t size = 0;
  CHECK(dg::cobs_encode(in, sizeof(in), out, sizeof(out), &size) == dg::Status::kOverflow);
}
