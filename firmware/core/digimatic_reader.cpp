// Digimatic pin-level reader: the CK interrupt only stores bits; poll() does the rest.
#include "firmware/core/digimatic_reader.h"

namespace dg {

DigimaticReader::DigimaticReader(hal::Board& board, DigimaticTiming timing)
    : ClockedProbe(board), timing_(timing) {}

void DigimaticReader::attach() {
  board_.on_rising_edge(hal::Pin::kGaugeClock, &DigimaticReader::on_clock_edge, this);
}

Status DigimaticReader::start() {
  if (state_ == State::kReading) return Status::kBusy;
  frame_ = DigimaticBits{};
  bits_ = 0;
  return begin_reading();
}

void DigimaticReader::on_clock_edge(void* context) {
  auto* self = static_cast<DigimaticReader*>(context);
  self->edges_ = self->edges_ + 1;
  if (self->state_ != State::kReading) return;
  const int index = self->bits_;
  if (index >= kDigimaticBits) {
    // More clocks than a frame has: the frame cannot be trusted.
    self->bits_ = index + 1;
    return;
  }
  self->frame_.set_bit(index, self->board_.read_pin(hal::Pin::kGaugeData));
  self->bits_ = index + 1;
  self->last_edge_us_ = self->board_.now_us();
  // The gauge sends one frame per request once clocking has begun; releasing
  // REQ now keeps it from starting a second frame.
  if (index == 0) self->board_.write_pin(hal::Pin::kGaugeReq, false);
}

uint64_t DigimaticReader::deadline_us() const {
  if (state_ != State::kReading) return UINT64_MAX;
  int bits = 0;
  uint64_t last_edge_us = 0;
  snapshot([&] { bits = bits_, last_edge_us = last_edge_us_; });
  return deadline_after(bits, last_edge_us);
}

uint64_t DigimaticReader::deadline_after(int bits, uint64_t last_edge_us) const {
  return bits == 0 ? started_us_ + timing_.first_clock_timeout_us : last_edge_us + timing_.bit_timeout_us;
}

DigimaticReader::State DigimaticReader::poll() {
  if (state_ != State::kReading) return state_;
  // The bits, then the deadline they give, then the clock: an edge after the snapshot can only
  // make the deadline later, never the clock earlier than an edge it counts.
  int bits = 0;
  uint64_t last_edge_us = 0;
  snapshot([&] { bits = bits_, last_edge_us = last_edge_us_; });
  const uint64_t deadline = deadline_after(bits, last_edge_us);
  if (bits > kDigimaticBits) {
    fail(Status::kBadEncoding);
  } else if (bits == kDigimaticBits) {
    if (digimatic_decode(frame_, &reading_) == Status::kOk) {
      state_ = State::kDone;
    } else {
      fail(Status::kBadEncoding);
    }
  } else if (board_.now_us() >= deadline) {
    // A missing clock edge leaves the frame short: an error, never a guess.
    fail(Status::kTimeout);
  }
  return state_;
}

}  // namespace dg
