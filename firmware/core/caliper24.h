// The 24-bit clock/data protocol of low-cost digital calipers and indicators: the instrument
// clocks out a frame by itself several times a second, least significant bit first. Bits 0-19
// are the magnitude (0.01 mm, or 0.0005 in with the inch bit), bit 20 the sign, bit 23 the inch
// flag; bits 21 and 22 are always 0 in this format (a frame with either set is refused).
#pragma once
#include <cstdint>

#include "common/status.h"
#include "firmware/core/probe.h"
#include "firmware/hal/board.h"

namespace dg {

constexpr int kCaliperBits = 24;

struct CaliperReading {
  int32_t counts = 0;  // signed, in the unit below
  bool inch = false;   // counts of 0.0005 in; else of 0.01 mm
};

// Decodes a complete frame (bit i of `raw` is the i-th bit received).
Status caliper24_decode(uint32_t raw, CaliperReading* out);
int64_t caliper24_to_nm(const CaliperReading& reading);

struct CaliperTiming {
  uint32_t frame_gap_us = 2000;       // a pause this long between edges separates frames
  uint32_t frame_timeout_us = 400000;  // two frame periods of an 8 Hz instrument, and margin
};

// Reads the first complete frame that begins after start(). The CK interrupt only stores bits;
// poll() decides. Asserting REQ enables the instrument's level shifter for the read.
class Caliper24Reader final : public ClockedProbe {
 public:
  Caliper24Reader(hal::Board& board, CaliperTiming timing);
  void attach();

  Status start() override;
  State poll() override;
  uint64_t deadline_us() const override;
  int64_t value_nm() const override { return caliper24_to_nm(reading_); }
  const CaliperReading& reading() const { return reading_; }

 private:
  static void on_clock_edge(void* self);
  void finish_frame(int bits, uint32_t raw);

  CaliperTiming timing_;
  CaliperReading reading_{};
  volatile uint32_t raw_ = 0;
  volatile int bits_ = 0;        // bits of the frame being received; -1: waiting for a frame start
};

}  // namespace dg
