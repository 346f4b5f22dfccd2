// Reads one Digimatic frame at the pin level: asserts REQ, samples DATA on each CK rising edge.
#pragma once
#include <cstdint>

#include "common/status.h"
#include "firmware/core/digimatic.h"
#include "firmware/hal/board.h"

namespace dg {

struct DigimaticTiming {
  uint32_t first_clock_timeout_us = 500000;  // REQ asserted -> first CK edge
  uint32_t bit_timeout_us = 20000;           // longest gap between two CK edges
};

class DigimaticReader {
 public:
  enum class State : uint8_t { kIdle, kReading, kDone, kFailed };

  DigimaticReader(hal::Board& board, DigimaticTiming timing);

  // Registers the CK edge interrupt; call once before the first read.
  void attach();
  // Starts a read; kBusy if one is running.
  Status start();
  // Advances timeouts and finishes the frame. Call from the main loop.
  State poll();
  State state() const { return state_; }
  // After kDone: the reading. After kFailed: why (kTimeout or kBadEncoding).
  const DigimaticReading& reading() const { return reading_; }
  Status error() const { return error_; }
  // Bits received in the current or last read (for diagnostics).
  int bits_received() const { return bits_; }
  // The time by which poll() must run again to notice a timeout.
  uint64_t deadline_us() const;

 private:
  static void on_clock_edge(void* self);
  void fail(Status why);

  hal::Board& board_;
  DigimaticTiming timing_;
  DigimaticBits frame_{};
  DigimaticReading reading_{};
  volatile int bits_ = 0;
  volatile uint64_t last_edge_us_ = 0;
  uint64_t started_us_ = 0;
  volatile State state_ = State::kIdle;
  Status error_ = Status::kOk;
};

}  // namespace dg
