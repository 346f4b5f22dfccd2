// Gauge model: quantises the part height, encodes the frame, then toggles CK bit by bit.
// DATA changes while CK is low and is read by the receiver on the CK rising edge.
#include "hw/sim/digimatic_gauge.h"

#include <cmath>

namespace dg::sim {

DigimaticGauge::DigimaticGauge(const GaugeConfig& config, uint64_t seed)
    : config_(config), random_(seed) {}

void DigimaticGauge::set_request(bool asserted, uint64_t now_ns, double height_mm) {
  const bool rising = asserted && !request_;
  request_ = asserted;
  if (!rising || sending_ || latching_ || config_.mute) return;
  request_ns_ = now_ns;
  request_height_mm_ = height_mm;
  if (config_.latch_delay_us == 0 && config_.latch_jitter_us == 0) {
    begin_frame(now_ns, height_mm);
    return;
  }
  double delay_us = config_.latch_delay_us;
  if (config_.latch_jitter_us > 0) delay_us += config_.latch_jitter_us * random_.gaussian();
  if (delay_us < 0) delay_us = 0;
  if (delay_us > config_.request_to_clock_us) delay_us = config_.request_to_clock_us;
  latching_ = true;
  next_event_ns_ = now_ns + static_cast<uint64_t>(std::llround(delay_us * 1000.0));
}

void DigimaticGauge::begin_frame(uint64_t now_ns, double height_mm) {
  double z = height_mm;
  if (config_.noise_sigma_mm > 0.0) z += config_.noise_sigma_mm * random_.gaussian();
  if (config_.outlier_rate > 0.0 && random_.uniform() < config_.outlier_rate) {
    z += random_.uniform() < 0.5 ? -config_.outlier_mm : config_.outlier_mm;
  }
  reading_ = DigimaticReading{};
  if (config_.inch) {
    reading_.unit = GaugeUnit::kInch;
    reading_.decimals = 4;
    reading_.value = static_cast<int32_t>(std::lround(z / 25.4 * 1e4));
  } else {
    reading_.unit = GaugeUnit::kMillimetre;
    reading_.decimals = 3;
    reading_.value = static_cast<int32_t>(std::lround(z * 1e3));
  }
  if (reading_.value > 999999) reading_.value = 999999;  // the display saturates
  if (reading_.value < -999999) reading_.value = -999999;
  digimatic_encode(reading_, &frame_);
  sending_ = true;
  bit_index_ = 0;
  clock_ = true;
  rise_next_ = false;
  latched_ns_ = now_ns;
  next_event_ns_ = request_ns_ + uint64_t{config_.request_to_clock_us} * 1000;
}

bool DigimaticGauge::advance(double height_mm) {
  if (latching_) {
    latching_ = false;
    begin_frame(next_event_ns_, height_mm);
    return false;
  }
  if (!sending_) {
    next_event_ns_ = UINT64_MAX;
    return false;
  }
  const uint64_t now = next_event_ns_;
  if (!rise_next_) {
    // Falling edge (none if CK is already low after a dropped pulse): present the bit.
    clock_ = false;
    data_ = bit(bit_index_);
    rise_next_ = true;
    next_event_ns_ = now + uint64_t{config_.clock_low_us} * 1000;
    return false;
  }
  // Rising edge: the receiver samples DATA now. A dropped pulse leaves CK low.
  const bool dropped = bit_index_ == config_.drop_rising_edge;
  if (!dropped) clock_ = true;
  rise_next_ = false;
  if (++bit_index_ == kDigimaticBits) {
    sending_ = false;
    clock_ = true;
    ++frames_sent_;
    next_event_ns_ = UINT64_MAX;
  } else {
    next_event_ns_ = now + uint64_t{config_.clock_high_us} * 1000;
  }
  return !dropped;
}

}  // namespace dg::sim
