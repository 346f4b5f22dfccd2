// A simulated low-cost caliper or indicator with the 24-bit clock/data output: free-running, a
// frame every 125 ms on a fixed schedule, clocked out while the reader enables the interface
// (REQ), measured at the start of each frame. Pin-level, in virtual nanoseconds.
#pragma once
#include <cstdint>

#include "firmware/core/caliper24.h"
#include "hw/sim/digimatic_gauge.h"
#include "hw/sim/random.h"

namespace dg::sim {

struct CaliperTimingConfig {
  uint32_t frame_period_us = 125000;  // about 8 readings a second
  uint32_t half_bit_us = 10;          // CK low and high
};

class CaliperGauge {
 public:
  CaliperGauge(const GaugeConfig& config, uint64_t seed, CaliperTimingConfig timing = {});

  void set_request(bool asserted, uint64_t now_ns);
  uint64_t next_event_ns() const { return next_event_ns_; }
  // Applies the change due at next_event_ns(), measuring `height_mm` when a frame begins; true on
  // a CK rising edge.
  bool advance(double height_mm);
  bool clock() const { return clock_; }
  bool data() const { return data_; }
  const CaliperReading& reading() const { return reading_; }
  uint32_t frames_sent() const { return frames_sent_; }

 private:
  uint64_t next_frame_start(uint64_t after_ns) const;

  GaugeConfig config_;
  CaliperTimingConfig timing_;
  Random random_;
  CaliperReading reading_{};
  uint32_t raw_ = 0;
  bool enabled_ = false;
  bool sending_ = false;
  bool rise_next_ = false;
  bool clock_ = false;
  bool data_ = false;
  int bit_index_ = 0;
  uint64_t next_event_ns_ = UINT64_MAX;
  uint32_t frames_sent_ = 0;
};

}  // namespace dg::sim
