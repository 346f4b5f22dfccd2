// The gauge readers against a CK interrupt that arrives between two reads of their main-loop code:
// a board double whose clock the test sets and which can fire the edge from inside a clock read.
#include <CppUTest/TestHarness.h>

#include <cstdint>

#include "firmware/core/caliper24.h"
#include "firmware/core/digimatic_reader.h"

namespace {

using dg::hal::Pin;

class RaceBoard final : public dg::hal::Board {
 public:
  void write_pin(Pin pin, bool level) override { pins_[static_cast<int>(pin)] = level; }
  bool read_pin(Pin pin) override { return pins_[static_cast<int>(pin)]; }
  void enable_drivers(bool) override {}
  void on_rising_edge(Pin, dg::hal::EdgeHandler handler, void* context) override {
    handler_ = handler;
    context_ = context;
  }
  void start_step_timer(uint32_t, dg::hal::TimerHandler, void*) override {}
  void stop_step_timer() override {}
  // Returns the time; if armed, the CK interrupt fires 1 us later, before the caller sees it.
  uint64_t now_us() override {
    const uint64_t t = time_us;
    if (armed_) {
      armed_ = false;
      time_us += 1;
      edge(armed_data_);
    }
    return t;
  }
  size_t link_write(const uint8_t*, size_t size) override { return size; }
  size_t link_read(uint8_t*, size_t) override { return 0; }
  bool wait(uint64_t) override { return true; }

  // A rising CK edge with DATA at `data`, now.
  void edge(bool data) {
    pins_[static_cast<int>(Pin::kGaugeData)] = data;
    if (handler_ != nullptr) handler_(context_);
  }
  // The next clock read is interrupted by an edge carrying `data`.
  void edge_inside_next_clock_read(bool data) {
    armed_ = true;
    armed_data_ = data;
  }

  uint64_t time_us = 1000000;

 private:
  bool pins_[static_cast<int>(Pin::kCount)] = {};
  dg::hal::EdgeHandler handler_ = nullptr;
  void* context_ = nullptr;
  bool armed_ = false, armed_data_ = false;
};

// 12.35 mm on the caliper: 1,235 counts of 0.01 mm, bits sent least significant first.
constexpr uint32_t kCaliperRaw = 1235;

// Sends caliper bits [from, to) 100 us apart.
void caliper_bits(RaceBoard& board, int from, int to) {
  for (int i = from; i < to; ++i) {
    board.time_us += 100;
    board.edge(((kCaliperRaw >> i) & 1u) != 0);
  }
}

}  // namespace

TEST_GROUP(GaugeEdgeRace){};

TEST(GaugeEdgeRace, AnEdgeWhilePollReadsTheClockDoesNotEndACaliperFrame) {
  // An edge between poll's clock read and its look at the last edge made the last edge later
  // than "now": the unsigned gap wrapped to a pause, and the frame ended at 10 bits.
  RaceBoard board;
  dg::Caliper24Reader reader(board, dg::CaliperTiming{});
  reader.attach();
  CHECK(reader.start() == dg::Status::kOk);
  board.time_us += 3000;  // the pause before a frame
  caliper_bits(board, 0, 10);
  board.time_us += 50;
  board.edge_inside_next_clock_read(((kCaliperRaw >> 10) & 1u) != 0);
  CHECK(reader.poll() == dg::Probe::State::kReading);
  caliper_bits(board, 11, dg::kCaliperBits);
  board.time_us += 3000;
  CHECK(reader.poll() == dg::Probe::State::kDone);
  LONGS_EQUAL(12350000, reader.value_nm());
}

TEST(GaugeEdgeRace, TheNextFramesFirstEdgeWhilePollReadsTheClockKeepsTheFrameBeforeIt) {
  // The pause after a frame has passed; the next frame's first edge arrives as poll reads the
  // clock. The frame before it is whole and is the reading (it was counted as 25 bits and lost).
  RaceBoard board;
  dg::Caliper24Reader reader(board, dg::CaliperTiming{});
  reader.attach();
  CHECK(reader.start() == dg::Status::kOk);
  board.time_us += 3000;
  caliper_bits(board, 0, dg::kCaliperBits);
  board.time_us += 2500;
  board.edge_inside_next_clock_read(true);
  CHECK(reader.poll() == dg::Probe::State::kDone);
  LONGS_EQUAL(12350000, reader.value_nm());
}

TEST(GaugeEdgeRace, ADigimaticFrameWithAnEdgeInsideEveryClockReadIsReadWhole) {
  // Every poll between two bits is interrupted by the next bit, the last 1 us before its
  // deadline: none may time out, and the 52 bits decode to the value sent.
  dg::DigimaticReading sent;
  sent.value = -123456;
  sent.decimals = 3;
  dg::DigimaticBits frame;
  CHECK(dg::digimatic_encode(sent, &frame) == dg::Status::kOk);
  auto bit = [&](int i) { return ((frame.digit[i / 4] >> (i % 4)) & 1u) != 0; };
  RaceBoard board;
  dg::DigimaticTiming timing;
  dg::DigimaticReader reader(board, timing);
  reader.attach();
  CHECK(reader.start() == dg::Status::kOk);
  board.time_us += 100;
  board.edge(bit(0));
  for (int i = 1; i < dg::kDigimaticBits; ++i) {
    board.time_us += timing.bit_timeout_us - 2;
    board.edge_inside_next_clock_read(bit(i));
    CHECK(reader.poll() == dg::Probe::State::kReading);
  }
  CHECK(reader.poll() == dg::Probe::State::kDone);
  LONGS_EQUAL(-123456000, reader.value_nm());
}
