// Frames: round trip, every corruption detected, resynchronisation after garbage.
#include "common/link/frame.h"

#include "common/link/crc32.h"

#include <CppUTest/TestHarness.h>

#include <vector>

namespace {

std::vector<uint8_t> make_frame(uint16_t seq, uint16_t ack, const std::vector<uint8_t>& payload) {
  std::vector<uint8_t> wire(dg::kFrameMaxWire);
  size_t size = 0;
  dg::FrameHeader header;
  header.seq = seq;
  header.ack = ack;
  CHECK(dg::frame_encode(header, payload.data(), payload.size(), wire.data(), wire.size(), &size) ==
        dg::Status::kOk);
  wire.resize(size);
  return wire;
}

struct Received {
  std::vector<std::vector<uint8_t>> payloads;
  std::vector<dg::FrameHeader> headers;
  int errors = 0;
};

Received feed_all(dg::FrameReader& decoder, const std::vector<uint8_t>& bytes) {
  Received r;
  size_t offset = 0;
  while (offset < bytes.size()) {
    size_t used = 0;
    const dg::Status s = decoder.feed(bytes.data() + offset, bytes.size() - offset, &used);
    offset += used;
    if (s == dg::Status::kOk) {
      r.payloads.emplace_back(decoder.payload(), decoder.payload() + decoder.payload_size());
      r.headers.push_back(decoder.header());
    } else if (s != dg::Status::kNeedMore) {
      ++r.errors;
    }
  }
  return r;
}

const std::vector<uint8_t> kPayload = {0x0A, 0x00, 0x12, 0x34, 0x00, 0x00, 0xFF, 0x01};

}  // namespace

TEST_GROUP(FrameDecoder){};

TEST(FrameDecoder, RoundTripsHeaderAndPayload) {
  dg::FrameDecoder decoder;
  const Received r = feed_all(decoder, make_frame(513, 77, kPayload));
  LONGS_EQUAL(1, r.payloads.size());
  CHECK(r.payloads[0] == kPayload);
  LONGS_EQUAL(513, r.headers[0].seq);
  LONGS_EQUAL(77, r.headers[0].ack);
}

TEST(FrameDecoder, DecodesFramesSplitIntoSingleBytes) {
  dg::FrameDecoder decoder;
  std::vector<uint8_t> stream = make_frame(1, 0, kPayload);
  const std::vector<uint8_t> second = make_frame(2, 0, {});
  stream.insert(stream.end(), second.begin(), second.end());
  int frames = 0;
  for (uint8_t byte : stream) {
    size_t used = 0;
    if (decoder.feed(&byte, 1, &used) == dg::Status::kOk) ++frames;
  }
  LONGS_EQUAL(2, frames);
}

TEST(FrameDecoder, RejectsBadCrc) {
  // Flip every bit of every byte in turn: the frame is never accepted.
  const std::vector<uint8_t> good = make_frame(9, 3, kPayload);
  for (size_t i = 1; i + 1 < good.size(); ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      std::vector<uint8_t> bad = good;
      bad[i] ^= static_cast<uint8_t>(1u << bit);
      dg::FrameDecoder decoder;
      const Received r = feed_all(decoder, bad);
      LONGS_EQUAL(0, r.payloads.size());
    }
  }
}

TEST(FrameDecoder, ResynchronisesAfterGarbage) {
  dg::FrameDecoder decoder;
  // Garbage with and without zero bytes, ending mid-"frame": the frame's own
  // leading delimiter cuts it off.
  std::vector<uint8_t> stream = {0x45, 0x99, 0x13, 0x00, 0x77, 0x00, 0x00, 0x21, 0x05, 0x66};
  const std::vector<uint8_t> frame = make_frame(5, 0, kPayload);
  stream.insert(stream.end(), frame.begin(), frame.end());
  const Received r = feed_all(decoder, stream);
  LONGS_EQUAL(1, r.payloads.size());
  CHECK(r.payloads[0] == kPayload);
  CHECK(r.errors >= 1);
  CHECK(decoder.counters().garbage_bytes > 0 || decoder.counters().bad_crc > 0 ||
        decoder.counters().bad_encoding > 0);
}

TEST(FrameDecoder, LosesOnlyTheDamagedFrameOfAStream) {
  dg::FrameDecoder decoder;
  std::vector<uint8_t> stream;
  for (uint16_t i = 0; i < 10; ++i) {
    std::vector<uint8_t> f = make_frame(i, 0, {static_cast<uint8_t>(i), 1, 2, 3});
    if (i == 4) f[2] ^= 0x40;   // corrupted
    if (i == 7) f.resize(4);    // cut short: the next frame's delimiter ends it
    stream.insert(stream.end(), f.begin(), f.end());
  }
  const Received r = feed_all(decoder, stream);
  LONGS_EQUAL(8, r.payloads.size());
  for (const auto& h : r.headers) CHECK(h.seq != 4 && h.seq != 7);
}

TEST(FrameDecoder, RecoversFromAnEndlessRunWithoutDelimiter) {
  dg::FrameDecoder decoder;
  std::vector<uint8_t> stream(5000, 0x55);
  stream.push_back(0x00);
  const std::vector<uint8_t> frame = make_frame(1, 0, kPayload);
  stream.insert(stream.end(), frame.begin(), frame.end());
  const Received r = feed_all(decoder, stream);
  LONGS_EQUAL(1, r.payloads.size());
  CHECK(decoder.counters().overflow >= 1);
}

// A device reads with room for the host's requests only: a longer frame is an overflow that costs
// only itself, frames of the room's size on either side of it arrive whole, and reset() makes it
// new again.
TEST(FrameDecoder, AReaderSizedForShortFramesSkipsALongOneAndKeepsTheRest) {
  dg::SizedFrameDecoder<16> decoder;
  const std::vector<uint8_t> fits(16, 0x00), longer(17, 0x07);
  std::vector<uint8_t> stream = make_frame(1, 0, fits);
  for (const auto& frame : {make_frame(2, 0, longer), make_frame(3, 0, fits)}) stream.insert(stream.end(), frame.begin(), frame.end());
  const Received r = feed_all(decoder, stream);
  LONGS_EQUAL(2, r.payloads.size());
  CHECK(r.payloads[0] == fits);
  CHECK(r.payloads[1] == fits);
  LONGS_EQUAL(3, r.headers[1].seq);
  LONGS_EQUAL(1, decoder.counters().overflow);
  LONGS_EQUAL(2, decoder.counters().frames);
  decoder.reset();
  LONGS_EQUAL(0, decoder.counters().frames);
  LONGS_EQUAL(0, decoder.counters().overflow);
}

TEST(FrameDecoder, RefusesOversizedPayload) {
  std::vector<uint8_t> payload(dg::kFrameMaxPayload + 1, 1);
  std::vector<uint8_t> wire(dg::kFrameMaxWire * 2);
  size_t size = 0;
  CHECK(dg::frame_encode({}, payload.data(), payload.size(), wire.data(), wire.size(), &size) ==
        dg::Status::kBadLength);
}

TEST(FrameDecoder, RejectsAnotherFrameVersion) {
  // A well-formed frame of link version 2 (good CRC, good stuffing) must not be read
  // as ours: only the version nibble can reject it.
  std::vector<uint8_t> raw = {static_cast<uint8_t>(((dg::kFrameVersion + 1) << 4) | 0), 1, 0, 0, 0};
  raw.insert(raw.end(), kPayload.begin(), kPayload.end());
  const uint32_t crc = dg::crc32(raw.data(), raw.size());
  for (int i = 0; i < 4; ++i) raw.push_back(static_cast<uint8_t>(crc >> (8 * i)));
  std::vector<uint8_t> wire(dg::cobs_max_encoded_size(raw.size()) + 2);
  size_t stuffed = 0;
  CHECK(dg::cobs_encode(raw.data(), raw.size(), wire.data() + 1, wire.size() - 2, &stuffed) ==
        dg::Status::kOk);
  wire[0] = 0;
  wire[1 + stuffed] = 0;
  wire.resize(stuffed + 2);
  dg::FrameDecoder decoder;
  LONGS_EQUAL(0, feed_all(decoder, wire).payloads.size());
}
