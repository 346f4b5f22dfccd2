// Reads one Digimatic frame at the pin level: asserts REQ, samples DATA on each CK rising edge.
#pragma once
#include <cstdint>

#include "common/status.h"
#include "firmware/core/digimatic.h"
#include "firmware/core/probe.h"
#include "firmware/hal/board.h"

namespace dg {

struct DigimaticTiming {
  uint32_t first_clock_timeout_us = 500000;  // REQ asserted -> first CK edge
  uint32_t bit_timeout_us = 20000;           // longest gap between two CK edges
};

class DigimaticReader final : public ClockedProbe {
 public:
  using State = Probe::State;

  DigimaticReader(hal::Board& board, DigimaticTiming timing);

  // Registers the CK edge interrupt; call once before the first read.
  void attach();
  Status start() override;
  State poll() override;
  State state() const { return state_; }
  // After kDone: the reading. After kFailed: why (kTimeout or kBadEncoding).
  const DigimaticReading& reading() const { return reading_; }
  int64_t value_nm() const override { return digimatic_to_nm(reading_); }
  // Bits received in the current or last read (for diagnostics).
  int bits_received() const { return bits_; }
  uint64_t deadline_us() const override;

 private:
  static void on_clock_edge(void* self);
  // When the next edge is due after `bits` edges, the last at `last_edge_us`.
  uint64_t deadline_after(int bits, uint64_t last_edge_us) const;

  DigimaticTiming timing_;
  DigimaticBits frame_{};
  DigimaticReading reading_{};
  volatile int bits_ = 0;
};

}  // namespace dg
