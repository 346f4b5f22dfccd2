// A frame is taken only whole: its first edge must follow a pause (so a frame already running at
// start() is skipped), it must have exactly 24 edges before the next pause, and bits 21-22 must
// be clear. Anything else is an error, never a value.
#include "firmware/core/caliper24.h"

namespace dg {

Status caliper24_decode(uint32_t raw, CaliperReading* out) {
  if (raw >> kCaliperBits != 0 || (raw & (3u << 21)) != 0) return Status::kBadEncoding;
  const int32_t magnitude = static_cast<int32_t>(raw & 0xFFFFFu);
  out->counts = (raw & (1u << 20)) != 0 ? -magnitude : magnitude;
  out->inch = (raw & (1u << 23)) != 0;
  return Status::kOk;
}

int64_t caliper24_to_nm(const CaliperReading& r) {
  // 0.0005 in = 12,700 nm exactly; 0.01 mm = 10,000 nm.
  return static_cast<int64_t>(r.counts) * (r.inch ? 12700 : 10000);
}

Caliper24Reader::Caliper24Reader(hal::Board& board, CaliperTiming timing) : ClockedProbe(board), timing_(timing) {}

void Caliper24Reader::attach() { board_.on_rising_edge(hal::Pin::kGaugeClock, &Caliper24Reader::on_clock_edge, this); }

Status Caliper24Reader::start() {
  if (state_ == State::kReading) return Status::kBusy;
  raw_ = 0;
  bits_ = -1;
  return begin_reading();
}

void Caliper24Reader::on_clock_edge(void* context) {
  auto* self = static_cast<Caliper24Reader*>(context);
  self->edges_ = self->edges_ + 1;
  if (self->state_ != State::kReading) return;
  const uint64_t now = self->board_.now_us();
  const bool after_pause = now - self->last_edge_us_ >= self->timing_.frame_gap_us;
  self->last_edge_us_ = now;
  if (self->bits_ < 0) {
    if (!after_pause) return;  // the tail of a frame that began before start()
    self->bits_ = 0;
    self->raw_ = 0;
  }
  const int index = self->bits_;
  if (index < kCaliperBits && self->board_.read_pin(hal::Pin::kGaugeData)) self->raw_ = self->raw_ | (1u << index);
  self->bits_ = index + 1;
}

// `bits` and `raw` as they were when the pause after the frame began: an edge after that starts the
// next frame and may still count itself in bits_, but it no longer changes raw_.
void Caliper24Reader::finish_frame(int bits, uint32_t raw) {
  board_.write_pin(hal::Pin::kGaugeReq, false);
  if (bits != kCaliperBits) return fail(Status::kBadEncoding);  // a lost or extra edge
  if (caliper24_decode(raw, &reading_) != Status::kOk) return fail(Status::kBadEncoding);
  state_ = State::kDone;
}

uint64_t Caliper24Reader::deadline_us() const {
  if (state_ != State::kReading) return UINT64_MAX;
  int bits = 0;
  uint64_t last_edge_us = 0;
  snapshot([&] { bits = bits_, last_edge_us = last_edge_us_; });
  // A frame in progress ends with the pause after it; waiting for one, the timeout.
  if (bits > 0) return last_edge_us + timing_.frame_gap_us;
  return started_us_ + timing_.frame_timeout_us;
}

Probe::State Caliper24Reader::poll() {
  if (state_ != State::kReading) return state_;
  int bits = 0;
  uint32_t raw = 0;
  uint64_t last_edge_us = 0;
  snapshot([&] { bits = bits_, raw = raw_, last_edge_us = last_edge_us_; });
  const uint64_t now = board_.now_us();
  if (bits > 0 && now - last_edge_us >= timing_.frame_gap_us) {
    finish_frame(bits, raw);
  } else if (bits <= 0 && now - started_us_ >= timing_.frame_timeout_us) {
    fail(Status::kTimeout);
  }
  return state_;
}

}  // namespace dg
