// What the scan engine needs of a gauge (start a reading, poll it, its deadline and its value), and
// the request bookkeeping the clocked gauges share.
#pragma once
#include <cstdint>

#include "common/status.h"
#include "firmware/hal/board.h"

namespace dg {

class Probe {
 public:
  enum class State : uint8_t { kIdle, kReading, kDone, kFailed };

  // Starts a read; kBusy if one is running.
  virtual Status start() = 0;
  // Advances timeouts and finishes the frame. Call from the main loop.
  virtual State poll() = 0;
  // The time by which poll() must run again to notice a timeout.
  virtual uint64_t deadline_us() const = 0;
  // After kDone: the reading in nanometres.
  virtual int64_t value_nm() const = 0;
  // After kFailed: why (kTimeout or kBadEncoding).
  virtual Status error() const = 0;

 protected:
  ~Probe() = default;
};

// What the gauges read through REQ and a clock line have in common: the reading's state, when it
// began, its last clock edge, why it failed, and REQ asserted while it runs. The CK interrupt of a
// derived reader stores bits; its poll() decides.
class ClockedProbe : public Probe {
 public:
  Status error() const override { return error_; }

 protected:
  explicit ClockedProbe(hal::Board& board) : board_(board) {}
  ~ClockedProbe() = default;

  // Starts the reading: call once the derived reader has cleared its frame, since the interrupt
  // takes bits as soon as the state says kReading.
  Status begin_reading() {
    error_ = Status::kOk;
    started_us_ = board_.now_us();
    last_edge_us_ = started_us_;
    state_ = State::kReading;
    board_.write_pin(hal::Pin::kGaugeReq, true);
    return Status::kOk;
  }
  void fail(Status why) {
    board_.write_pin(hal::Pin::kGaugeReq, false);
    error_ = why;
    state_ = State::kFailed;
  }

  // Reads what the CK interrupt writes as one consistent state: `read` runs again until no edge
  // came during it. last_edge_us_ is two words on a 32-bit core, and an edge between the two
  // loads, or between reading it and the count of bits, would give a time or a count that never
  // was. Read the clock after this, so that no edge in the snapshot is later than "now".
  template <typename Read>
  void snapshot(Read read) const {
    for (;;) {
      const uint32_t before = edges_;
      read();
      if (edges_ == before) return;
    }
  }

  hal::Board& board_;
  volatile uint32_t edges_ = 0;  // every CK edge seen, counted first thing by the interrupt
  volatile uint64_t last_edge_us_ = 0;
  uint64_t started_us_ = 0;
  volatile State state_ = State::kIdle;
  Status error_ = Status::kOk;
};

}  // namespace dg
