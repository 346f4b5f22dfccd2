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
  return bits_ == 0 ? started_us_ + timing_.first_clock_timeout_us
                    : last_edge_us_ + timing_.bit_timeout_us;
}

DigimaticReader::State DigimaticReader::poll() {
  if (state_ != State::kReading) return state_;
  const int bits = bits_;
  if (bits > kDigimaticBits) {
    fail(Status::kBadEncoding);
  } else if (bits == kDigimaticBits) {
    if (digimatic_decode(frame_, &reading_) == Status::kOk) {
      state_ = State::kDone;
    } else {
      fail(Status::kBadEncoding);
    }
  } else if (board_.now_us() >= deadline_us()) {
    // A missing clock edge leaves the frame short: an error, never a guess.
    fail(Status::kTimeout);
  }
  return state_;
}

}  // namespace dg
