// Virtual time advances only in wait(): to the next step tick, gauge clock edge or
// deadline. Step ticks are handled in a batch; the firmware wakes when a move ends,
// on every gauge edge, at its deadline, or when the host has sent bytes.
#include "hw/sim/sim_board.h"

#include <algorithm>

namespace dg::sim {

namespace {
int index(hal::Pin pin) { return static_cast<int>(pin); }
}  // namespace

SimBoard::SimBoard(const SimConfig& config, LinkPort* link)
    : config_(config),
      link_(link),
      gauge_(config.gauge, config.seed),
      caliper_(config.gauge, config.seed),
      x_steps_(config.start_x_steps),
      y_steps_(config.start_y_steps) {
  // The table was last moved positive (as homing's pull-off leaves it): the nut bears on the
  // screw's positive side.
  motor_[0] = x_steps_ + config.backlash_steps;
  motor_[1] = y_steps_ + config.backlash_steps;
  if (config.machine.flatness_um != 0) flatness_peak_ = flatness_map_peak(config.machine.map_seed);
}

double SimBoard::height_under_probe_mm() const {
  const MachineErrors& e = config_.machine;
  if (!e.any()) return config_.part.height_mm(table_x_mm(), table_y_mm());
  double x_mm = 0, y_mm = 0;
  actual_table_xy(e, table_x_mm(), table_y_mm(), &x_mm, &y_mm);
  // The carriage's height error and the stand's drift raise the whole part under the tip.
  const double raised_mm = travel_z_error_mm(e, flatness_peak_, table_x_mm(), table_y_mm()) + drift_mm(e, now_ns_);
  const double gauge_scale = 1 + e.gauge_scale_ppm * 1e-6;
  if (e.gauge_tilt_x_urad == 0 && e.gauge_tilt_y_urad == 0) return (config_.part.height_mm(x_mm, y_mm) + raised_mm) * gauge_scale;
  return gauge_scale *
         tilted_reading_mm(e, [&](double dx_mm, double dy_mm) { return config_.part.height_mm(x_mm + dx_mm, y_mm + dy_mm) + raised_mm; });
}

void SimBoard::track_plunger() {
  // Between two calls the table stands still, so the surface under the tip is constant and the
  // plunger's fall is exact: it lands on the surface or is still above it.
  const double surface_mm = height_under_probe_mm();
  double at_mm = surface_mm;
  if (plunger_known_) {
    const double fallen_mm = config_.plunger_mm_s * static_cast<double>(now_ns_ - plunger_ns_) * 1e-9;
    if (plunger_at_mm_ - fallen_mm > surface_mm) at_mm = plunger_at_mm_ - fallen_mm;
  }
  plunger_at_mm_ = at_mm;
  plunger_ns_ = now_ns_;
  plunger_known_ = true;
}

double SimBoard::plunger_mm() {
  if (config_.plunger_mm_s <= 0) return height_under_probe_mm();
  track_plunger();
  return plunger_at_mm_;
}

void SimBoard::step_axis(int axis) {
  if (config_.plunger_mm_s > 0) track_plunger();
  const bool positive = pins_[index(axis == 0 ? hal::Pin::kDirX : hal::Pin::kDirY)];
  int64_t& position = axis == 0 ? x_steps_ : y_steps_;
  int64_t& motor = motor_[axis];
  const int64_t before = position;
  const bool touching_before = touching();
  if (!drivers_on_) {
    ++steps_without_drivers_;
    return;
  }
  if (!positive && position <= config_.hard_stop_steps) {
    ++lost_steps_;  // against the mechanical stop: the motor stalls
  } else {
    // The nut sits somewhere in the screw's play [motor - backlash, motor]: the motor pushes the
    // table only from the ends of that band.
    motor += positive ? 1 : -1;
    if (positive && position < motor - config_.backlash_steps) position = motor - config_.backlash_steps;
    if (!positive && position > motor) position = motor;
  }
  if ((position < 0) != (before < 0)) switch_edge_ns_[axis] = now_ns_;
  if (touching() && !touching_before) touch_edge_due_ = true;
  ++steps_;
  if (axis == 0 && x_step_log_ != nullptr) x_step_log_->push_back(now_ns_);
  if (last_step_ns_[axis] != kNever) {
    const uint64_t interval = now_ns_ - last_step_ns_[axis];
    if (interval < min_step_interval_ns_) min_step_interval_ns_ = interval;
  }
  last_step_ns_[axis] = now_ns_;
}

void SimBoard::write_pin(hal::Pin pin, bool level) {
  const bool was = pins_[index(pin)];
  pins_[index(pin)] = level;
  if (level && !was) {
    if (pin == hal::Pin::kStepX) step_axis(0);
    if (pin == hal::Pin::kStepY) step_axis(1);
  }
  if (pin == hal::Pin::kGaugeReq && level != was) {
    if (config_.caliper) {
      caliper_.set_request(level, now_ns_);
    } else {
      gauge_.set_request(level, now_ns_, plunger_mm());
    }
  }
}

// The logical level of a normally-closed min switch: tripped while its circuit is open.
bool SimBoard::limit_tripped(int axis) const {
  if (config_.switches == SwitchWiring::kOpen) return true;
  if (config_.switches == SwitchWiring::kStuckClosed) return false;
  if (axis == 0 && config_.x_wire_cut_at_ns > 0 && now_ns_ >= config_.x_wire_cut_at_ns) return true;
  const bool pressed = (axis == 0 ? x_steps_ : y_steps_) < 0;
  const uint64_t edge = switch_edge_ns_[axis];
  if (config_.switch_bounce_ns > 0 && edge != kNever && now_ns_ - edge < config_.switch_bounce_ns) {
    // Chatter: the contacts make and break every 3 us until they settle.
    return ((now_ns_ - edge) / 3000) % 2 ? pressed : !pressed;
  }
  return pressed;
}

bool SimBoard::glitch() const {
  return config_.glitch_period_ns > 0 && now_ns_ % config_.glitch_period_ns < 2000;
}

bool SimBoard::read_pin(hal::Pin pin) {
  switch (pin) {
    case hal::Pin::kGaugeClock: return config_.caliper ? caliper_.clock() : gauge_.clock();
    case hal::Pin::kGaugeData: return config_.caliper ? caliper_.data() : gauge_.data();
    case hal::Pin::kLimitXMin: return limit_tripped(0) || glitch();
    case hal::Pin::kLimitYMin: return limit_tripped(1) || glitch();
    case hal::Pin::kTouchProbe:
      return touching();
    case hal::Pin::kEstop:
      return glitch() ||
             (config_.estop_for_ns > 0 && now_ns_ >= config_.estop_at_ns && now_ns_ < config_.estop_at_ns + config_.estop_for_ns);
    default: return pins_[index(pin)];
  }
}

void SimBoard::on_rising_edge(hal::Pin pin, hal::EdgeHandler handler, void* context) {
  if (pin == hal::Pin::kGaugeClock) {
    clock_handler_ = handler;
    clock_context_ = context;
  } else if (pin == hal::Pin::kEstop) {
    estop_handler_ = handler;
    estop_context_ = context;
  } else if (pin == hal::Pin::kTouchProbe) {
    touch_handler_ = handler;
    touch_context_ = context;
  }
}

void SimBoard::take_touch_edge() {
  if (!touch_edge_due_) return;
  touch_edge_due_ = false;
  if (touch_handler_ != nullptr) touch_handler_(touch_context_);
}

uint64_t SimBoard::estop_edge_ns(bool spikes) const {
  uint64_t edge = kNever;
  if (config_.estop_for_ns > 0 && config_.estop_at_ns > now_ns_) edge = config_.estop_at_ns;
  if (spikes && config_.glitch_period_ns > 0) {
    const uint64_t spike = (now_ns_ / config_.glitch_period_ns + 1) * config_.glitch_period_ns;
    if (spike < edge) edge = spike;
  }
  return edge;
}

uint32_t SimBoard::fire_step_timer() {
  const uint32_t delay = timer_handler_(timer_context_);
  timer_next_ns_ = delay == 0 ? kNever : now_ns_ + delay;
  // A touch edge raised during the step is taken after it: the step interrupt outranks it.
  take_touch_edge();
  return delay;
}

void SimBoard::run_timer_until(uint64_t until_ns) {
  while (timer_next_ns_ <= until_ns) {
    now_ns_ = timer_next_ns_;
    fire_step_timer();
  }
  now_ns_ = until_ns;
}

void SimBoard::spin_ns(uint32_t ns) { run_timer_until(now_ns_ + ns); }

void SimBoard::start_step_timer(uint32_t delay_ns, hal::TimerHandler handler, void* context) {
  timer_handler_ = handler;
  timer_context_ = context;
  timer_next_ns_ = now_ns_ + (delay_ns == 0 ? 1 : delay_ns);
}

void SimBoard::stop_step_timer() { timer_next_ns_ = kNever; }

size_t SimBoard::link_write(const uint8_t* data, size_t size) {
  if (link_ == nullptr) return size;
  return link_->write(data, size);
}

size_t SimBoard::link_read(uint8_t* data, size_t capacity) {
  if (link_ == nullptr) return 0;
  if (!link_hint_ && now_ns_ - last_link_poll_ns_ < kLinkPollNs) return 0;
  last_link_poll_ns_ = now_ns_;
  const size_t got = link_->read(data, capacity);
  link_hint_ = got > 0;
  return got;
}

namespace {
// Real time a firmware deadline may wait for the host before virtual time jumps to it.
constexpr long kStallRealMs = 250;
}  // namespace

void SimBoard::watchdog_start(uint32_t timeout_ms) {
  watchdog_timeout_ns_ = static_cast<uint64_t>(timeout_ms) * 1000000;
  watchdog_kicked_ns_ = now_ns_;
}

void SimBoard::watchdog_kick() { watchdog_kicked_ns_ = now_ns_; }

bool SimBoard::take_reset() {
  const bool pending = reset_pending_;
  reset_pending_ = false;
  return pending;
}

bool SimBoard::wait(uint64_t deadline_us) {
  // A missed kick resets the board: the firmware's loop ends, the motors stop with it.
  auto watchdog_reset = [this] {
    // At its expiry, or now if a wait already ran past it: virtual time never goes back.
    const uint64_t expiry_ns = watchdog_kicked_ns_ + watchdog_timeout_ns_;
    if (expiry_ns > now_ns_) now_ns_ = expiry_ns;
    timer_next_ns_ = kNever;
    watchdog_timeout_ns_ = kNever;  // a reset stops it until the firmware starts it again
    reset_cause_ = hal::ResetCause::kWatchdog;
    reset_pending_ = true;
    return false;
  };
  if (config_.hang_at_ns > 0 && !hung_ && now_ns_ >= config_.hang_at_ns) {
    // The loop hangs here: nothing comes back to kick the watchdog, which then resets the board;
    // without one the device is dead for good.
    hung_ = true;
    if (watchdog_timeout_ns_ == kNever) return false;
    return watchdog_reset();
  }
  if (watchdog_timeout_ns_ != kNever && now_ns_ > watchdog_kicked_ns_ + watchdog_timeout_ns_) return watchdog_reset();
  const uint64_t deadline_ns = deadline_us == kNever ? kNever : deadline_us * 1000;
  for (;;) {
    if (link_ != nullptr && link_->closed()) return false;
    if (deadline_ns <= now_ns_) return true;
    const uint64_t gauge_ns = gauge_event_ns();
    uint64_t next = timer_next_ns_ < gauge_ns ? timer_next_ns_ : gauge_ns;
    if (deadline_ns < next) next = deadline_ns;
    // Pressing the e-stop is an interrupt: the firmware wakes to it, and its edge handler (the
    // hardware path), if attached, runs first; so does a spike's edge, only while time runs anyway
    // (an idle machine's virtual time waits for its host).
    const uint64_t edge = estop_edge_ns(estop_handler_ != nullptr && next != kNever);
    if (edge != kNever && edge <= next) {
      now_ns_ = edge;
      if (estop_handler_ != nullptr) estop_handler_(estop_context_);
      return true;
    }
    if (link_ != nullptr && now_ns_ - last_link_poll_ns_ >= kLinkPollNs) {
      return true;  // the firmware's poll looks at the link
    }
    if (next == kNever) {
      // Nothing will happen until the host speaks.
      if (link_ == nullptr || !link_->wait_readable()) return false;
      link_hint_ = true;
      return true;
    }
    if (link_ != nullptr && next == deadline_ns && timer_next_ns_ == kNever && gauge_ns == kNever) {
      // Only the firmware's own deadline is pending: a retransmission timer while it waits for
      // the host. Virtual time stands still while the host answers (so a scan stays the same
      // whatever the machine's load); 250 ms of real time spent waiting for this deadline (a
      // lost frame) lets the timer run out, however long the timer is in virtual time. With a
      // real clock the 250 ms count from the first wait for it, not from the host's last byte:
      // a host that keeps talking (acknowledgements, status requests) while a frame of ours was
      // lost must not hold the timer back for ever.
      long wait_ms = kStallRealMs;
      if (real_ms_ != nullptr) {
        const uint64_t real_now_ms = real_ms_();
        if (stalled_deadline_ns_ != deadline_ns) {
          stalled_deadline_ns_ = deadline_ns;
          stalled_since_ms_ = real_now_ms;
        }
        const uint64_t waited_ms = real_now_ms - stalled_since_ms_;
        wait_ms = waited_ms < static_cast<uint64_t>(kStallRealMs) ? kStallRealMs - static_cast<long>(waited_ms) : 0;
      }
      if (wait_ms > 0 && link_->wait_readable(static_cast<int>(wait_ms))) {
        link_hint_ = true;
        return true;
      }
      if (link_->closed()) return false;
      now_ns_ = deadline_ns;
      return true;
    }
    now_ns_ = next;
    if (next == deadline_ns) return true;
    if (next == gauge_ns) {
      const bool rising = config_.caliper ? caliper_.advance(plunger_mm()) : gauge_.advance(plunger_mm());
      if (rising && clock_handler_ != nullptr) {
        clock_handler_(clock_context_);
        return true;
      }
      continue;
    }
    if (fire_step_timer() == 0) return true;  // the move ended: the firmware has work
  }
}

bool SimBoard::store_bytes(const uint8_t* data, size_t size) {
  if (size > sizeof settings_) return false;
  for (size_t k = 0; k < size; ++k) settings_[k] = data[k];
  settings_size_ = size;
  return true;
}

bool SimBoard::store_settings(const uint8_t* data, size_t size) {
  if (!store_bytes(data, size)) return false;
  return settings_hook_ != nullptr && settings_hook_(data, size, settings_context_);
}

size_t SimBoard::load_settings(uint8_t* data, size_t capacity) {
  if (settings_size_ > capacity) return 0;
  for (size_t k = 0; k < settings_size_; ++k) data[k] = settings_[k];
  return settings_size_;
}

}  // namespace dg::sim
