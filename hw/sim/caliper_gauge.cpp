// Frames start at multiples of the frame period (the instrument's own clock), so a reader waits
// for the next one as it would on the bench. DATA is set while CK is low and read on its rise.
#include "hw/sim/caliper_gauge.h"

#include <cmath>

namespace dg::sim {

CaliperGauge::CaliperGauge(const GaugeConfig& config, uint64_t seed, CaliperTimingConfig timing)
    : config_(config), timing_(timing), random_(seed ^ 0x9e3779b97f4a7c15ull) {}

uint64_t CaliperGauge::next_frame_start(uint64_t after_ns) const {
  const uint64_t period = uint64_t{timing_.frame_period_us} * 1000;
  return (after_ns / period + 1) * period;
}

void CaliperGauge::set_request(bool asserted, uint64_t now_ns) {
  enabled_ = asserted && !config_.mute;
  if (!enabled_) {
    // The interface is off: whatever the instrument sends does not reach the reader.
    sending_ = false;
    clock_ = false;
    next_event_ns_ = UINT64_MAX;
    return;
  }
  if (!sending_ && next_event_ns_ == UINT64_MAX) next_event_ns_ = next_frame_start(now_ns);
}

bool CaliperGauge::advance(double height_mm) {
  if (!enabled_) {
    next_event_ns_ = UINT64_MAX;
    return false;
  }
  const uint64_t now = next_event_ns_;
  if (!sending_) {
    // A frame begins: measure and encode.
    double z = height_mm;
    if (config_.noise_sigma_mm > 0.0) z += config_.noise_sigma_mm * random_.gaussian();
    if (config_.outlier_rate > 0.0 && random_.uniform() < config_.outlier_rate) {
      z += random_.uniform() < 0.5 ? -config_.outlier_mm : config_.outlier_mm;
    }
    reading_.inch = config_.inch;
    long counts = std::lround(config_.inch ? z / 25.4 * 2000 : z * 100);
    if (counts > 0xFFFFF) counts = 0xFFFFF;
    if (counts < -0xFFFFF) counts = -0xFFFFF;
    reading_.counts = static_cast<int32_t>(counts);
    raw_ = static_cast<uint32_t>(counts < 0 ? -counts : counts) | (counts < 0 ? 1u << 20 : 0u) | (config_.inch ? 1u << 23 : 0u);
    sending_ = true;
    bit_index_ = 0;
    rise_next_ = false;
  }
  if (!rise_next_) {
    clock_ = false;
    data_ = (raw_ >> bit_index_) & 1u;
    rise_next_ = true;
    next_event_ns_ = now + uint64_t{timing_.half_bit_us} * 1000;
    return false;
  }
  const bool dropped = bit_index_ == config_.drop_rising_edge;
  if (!dropped) clock_ = true;
  rise_next_ = false;
  if (++bit_index_ == kCaliperBits) {
    sending_ = false;
    clock_ = false;
    ++frames_sent_;
    next_event_ns_ = next_frame_start(now);
  } else {
    next_event_ns_ = now + uint64_t{timing_.half_bit_us} * 1000;
  }
  return !dropped;
}

}  // namespace dg::sim
