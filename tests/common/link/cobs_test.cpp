// COBS: no zero bytes after encoding, exact round trips, and rejected bad input.
#include "common/link/cobs.h"

#include <CppUTest/TestHarness.h>

#include <random>
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

// A frame is stuffed piece by piece (header, payload, CRC) so that no copy of it sits on a device's
// stack: any split of any input gives the bytes of one cobs_encode, runs of 254 and zeros across
// the pieces' seams included.
TEST(Cobs, AWriterFedInPiecesEncodesAsOneCall) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<uint8_t> in(rng() % 700);
    for (auto& b : in) b = static_cast<uint8_t>(rng() % 4 == 0 ? 0 : 1 + rng() % 255);
    if (trial % 3 == 0) std::fill(in.begin(), in.end(), 0x5A);  // runs of 254 non-zero bytes
    std::vector<uint8_t> whole(dg::cobs_max_encoded_size(in.size()));
    size_t whole_size = 0;
    CHECK(dg::cobs_encode(in.data(), in.size(), whole.data(), whole.size(), &whole_size) == dg::Status::kOk);
    std::vector<uint8_t> pieces(whole.size());
    dg::CobsWriter writer(pieces.data(), pieces.size());
    for (size_t at = 0; at < in.size();) {
      const size_t length = std::min<size_t>(in.size() - at, rng() % 300);
      writer.put(in.data() + at, length);
      at += length;
    }
    size_t pieces_size = 0;
    CHECK(writer.finish(&pieces_size) == dg::Status::kOk);
    LONGS_EQUAL(whole_size, pieces_size);
    CHECK(std::equal(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(whole_size), pieces.begin()));
  }
}

// A writer whose output is too small says so and writes nothing past its end.
TEST(Cobs, AWriterWithTooLittleRoomOverflowsWithoutWritingPastIt) {
  std::vector<uint8_t> in(300, 0x33);
  in[100] = 0;
  // 301 bytes encoded: a code and 100 bytes, then a code and 199.
  for (size_t room = 0; room < 301; room += 7) {
    std::vector<uint8_t> out(room + 16, 0xEE);
    dg::CobsWriter writer(out.data(), room);
    writer.put(in.data(), in.size());
    size_t size = 0;
    CHECK(writer.finish(&size) == dg::Status::kOverflow);
    for (size_t i = room; i < out.size(); ++i) LONGS_EQUAL(0xEE, out[i]);
  }
  std::vector<uint8_t> out(301);
  dg::CobsWriter writer(out.data(), out.size());
  writer.put(in.data(), in.size());
  size_t size = 0;
  CHECK(writer.finish(&size) == dg::Status::kOk);
  LONGS_EQUAL(301, size);
}
