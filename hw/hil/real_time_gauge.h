// hw/sim's Digimatic gauge model clocked in real time, for programs that play a gauge on real or
// simulated lines (the HIL rig, the system tests). The model's frame is a schedule of CK changes;
// a player that wakes late shifts the rest of the frame by its lateness instead of catching up, so
// no CK phase is ever shorter than configured (a collapsed pulse would be a lost bit).
#pragma once
#include <cstdint>

#include "hw/sim/digimatic_gauge.h"

namespace dg::hil {

class RealTimeGauge {
 public:
  // `start_ns`: the player's clock now (any monotonic clock, in ns).
  RealTimeGauge(const sim::GaugeConfig& config, uint64_t start_ns) : model_(config, 1), epoch_ns_(start_ns) {}

  // REQ changed at `now_ns`; when asserted the gauge measures `height_mm` and starts a frame.
  void set_request(bool asserted, uint64_t now_ns, double height_mm) {
    model_.set_request(asserted, now_ns - epoch_ns_, height_mm);
  }
  // When the next CK change is due on the player's clock, or UINT64_MAX when quiet.
  uint64_t due_ns() const {
    const uint64_t due = model_.next_event_ns();
    return due == UINT64_MAX ? UINT64_MAX : epoch_ns_ + due;
  }
  // Makes the change due by `now_ns`, if any (one per call); true when CK or DATA changed.
  bool advance(uint64_t now_ns);

  bool clock() const { return model_.clock(); }
  bool data() const { return model_.data(); }
  const sim::DigimaticGauge& model() const { return model_; }

 private:
  sim::DigimaticGauge model_;
  uint64_t epoch_ns_;  // the model's time zero; slides when the player runs late
};

}  // namespace dg::hil
