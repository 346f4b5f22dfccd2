// A simulated Mitutoyo Digimatic gauge at the pin level: answers REQ by clocking a
// 52-bit frame out on CK/DATA with the specified timing, in virtual nanoseconds.
#pragma once
#include <cstdint>

#include "firmware/core/digimatic.h"
#include "hw/sim/random.h"

namespace dg::sim {

struct GaugeConfig {
  bool inch = false;                 // mm at 0.001 (1 um) or inch at 0.0001
  double noise_sigma_mm = 0.0;       // Gaussian noise added to each reading
  double outlier_rate = 0.0;         // probability that a reading is a gross outlier
  double outlier_mm = 0.5;           // size of an outlier (sign random)
  // Timing after the Digimatic output specification: CK low and high phases of
  // 0.2-0.4 ms each; the first clock follows REQ within the gauge's response time.
  uint32_t request_to_clock_us = 5000;
  uint32_t clock_low_us = 200;
  uint32_t clock_high_us = 200;
  // When the gauge takes its reading after REQ rises, and the spread of that moment (a Gaussian
  // sigma): a gauge latches its count a little after the request, which a table moving under it
  // turns into a shift along the motion. Must end before the first clock (request_to_clock_us).
  uint32_t latch_delay_us = 0;
  uint32_t latch_jitter_us = 0;
  // Fault injection for tests: the rising edge of this bit never happens (-1: none).
  int drop_rising_edge = -1;
  // Fault injection: the gauge never answers REQ.
  bool mute = false;
};

class DigimaticGauge {
 public:
  DigimaticGauge(const GaugeConfig& config, uint64_t seed);

  // REQ changed. When asserted, the gauge reads `height_mm` and starts a frame; with a latch delay
  // it takes its reading that much later instead (the next event: see advance()).
  void set_request(bool asserted, uint64_t now_ns, double height_mm);
  // Time of the next event (the latch or a CK change), or UINT64_MAX when quiet.
  uint64_t next_event_ns() const { return next_event_ns_; }
  // Applies the event due at next_event_ns(): at the latch the gauge reads `height_mm` (where the
  // plunger is now); returns true on a rising CK edge.
  bool advance(double height_mm);
  // The same where nothing moves under the gauge: the latch reads what was there at REQ.
  bool advance() { return advance(request_height_mm_); }
  // When the last reading was latched (virtual ns).
  uint64_t latched_ns() const { return latched_ns_; }

  bool clock() const { return clock_; }
  bool data() const { return data_; }
  const GaugeConfig& config() const { return config_; }
  // The reading the gauge is sending or last sent.
  const DigimaticReading& reading() const { return reading_; }
  uint32_t frames_sent() const { return frames_sent_; }

 private:
  void begin_frame(uint64_t now_ns, double height_mm);
  bool bit(int index) const { return (frame_.digit[index / 4] >> (index % 4)) & 1u; }

  GaugeConfig config_;
  Random random_;
  DigimaticBits frame_{};
  DigimaticReading reading_{};
  bool request_ = false;
  bool sending_ = false;
  bool latching_ = false;   // REQ came; the reading is taken at next_event_ns_
  uint64_t request_ns_ = 0;
  double request_height_mm_ = 0;
  uint64_t latched_ns_ = 0;
  bool rise_next_ = false;  // the next CK event is the rising half of the bit
  bool clock_ = true;   // CK idles high
  bool data_ = false;
  int bit_index_ = 0;
  uint64_t next_event_ns_ = UINT64_MAX;
  uint32_t frames_sent_ = 0;
};

}  // namespace dg::sim
