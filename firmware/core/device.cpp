// Device message handling and the transmit scheduler (replies first, then points, then ScanDone).
#include "firmware/core/device.h"

#include "common/proto/messages.h"

namespace dg {

Device::Device(hal::Board& board, const DeviceConfig& config)
    : board_(board),
      config_(config),
      motion_(board, config.motion),
      gauge_(board, config.gauge),
      caliper_(board, config.caliper),
      scan_(board, motion_,
            config.probe == digitizer_ProbeType_PROBE_CALIPER_24BIT ? static_cast<Probe&>(caliper_) : static_cast<Probe&>(gauge_),
            config.scan),
      homing_(motion_),
      repeat_(motion_, config.probe == digitizer_ProbeType_PROBE_CALIPER_24BIT ? static_cast<Probe&>(caliper_)
                                                                              : static_cast<Probe&>(gauge_)),
      link_(config.retransmit_us) {}

namespace {

digitizer_ResetCause reset_cause_name(hal::ResetCause cause) {
  switch (cause) {
    case hal::ResetCause::kPowerOn: return digitizer_ResetCause_RESET_POWER_ON;
    case hal::ResetCause::kPin: return digitizer_ResetCause_RESET_PIN;
    case hal::ResetCause::kWatchdog: return digitizer_ResetCause_RESET_WATCHDOG;
    case hal::ResetCause::kSoftware: return digitizer_ResetCause_RESET_SOFTWARE;
    case hal::ResetCause::kBrownOut: return digitizer_ResetCause_RESET_BROWN_OUT;
    case hal::ResetCause::kUnknown: break;
  }
  return digitizer_ResetCause_RESET_UNKNOWN;
}

}  // namespace

void Device::begin() {
  if (config_.probe == digitizer_ProbeType_PROBE_CALIPER_24BIT) {
    caliper_.attach();
  } else {
    gauge_.attach();
  }
  board_.write_pin(hal::Pin::kGaugeReq, false);
  motion_.attach_estop();
  motion_.attach_probe();
  // The calibration's summary a board stored before: damaged or absent bytes leave none.
  uint8_t stored[digitizer_CalibrationSummary_size];
  const size_t stored_size = board_.load_settings(stored, sizeof stored);
  if (stored_size > 0 && decode_calibration_summary(stored, stored_size, &calibration_) == Status::kOk) {
    has_calibration_ = calibration_kept_ = true;
  }
  if (config_.watchdog_ms > 0) board_.watchdog_start(config_.watchdog_ms);
}

void Device::run() {
  begin();
  for (;;) {
    poll();
    if (!board_.wait(next_deadline_us())) return;
  }
}

digitizer_DeviceState Device::state() const {
  if (alarm_) return digitizer_DeviceState_STATE_ALARM;
  if (scan_.active()) {
    return scan_.paused() ? digitizer_DeviceState_STATE_PAUSED : digitizer_DeviceState_STATE_SCANNING;
  }
  if (homing_.active()) return digitizer_DeviceState_STATE_HOMING;
  if (jogging_ || repeat_.active() || touching_) return digitizer_DeviceState_STATE_JOGGING;
  return digitizer_DeviceState_STATE_IDLE;
}

size_t Device::first_unsent_offset() const {
  // The ring holds seqs [oldest, oldest + size); everything from next_send_seq_ is unsent.
  return ring_.empty() ? 0 : next_send_seq_ - ring_.at(0).seq;
}

uint64_t Device::next_deadline_us() const {
  uint64_t deadline = scan_.deadline_us();
  if (repeat_.deadline_us() < deadline) deadline = repeat_.deadline_us();
  const uint64_t resend = link_.next_deadline_us(UINT64_MAX);
  if (resend < deadline) deadline = resend;
  // An unsent partial batch must go out when it is old enough, once the link has room for it
  // (with a full window the device waits for the host's acknowledgements, not for a time).
  const size_t offset = first_unsent_offset();
  if (offset < ring_.size() && !link_.window_full()) {
    const uint64_t due = ring_.at(offset).t_us + kBatchMaxAgeUs;
    if (due < deadline) deadline = due;
  }
  // A first sight of the e-stop is looked at again once the confirming delay has passed.
  if (estop_seen_us_ != kNotSeen && !estop_confirmed_ && estop_seen_us_ + kEstopConfirmUs < deadline) {
    deadline = estop_seen_us_ + kEstopConfirmUs;
  }
  const uint64_t silence = host_silence_deadline_us();
  if (silence < deadline) deadline = silence;
  // The watchdog counts while the board sleeps: wake in time to kick it.
  if (config_.watchdog_ms > 0) {
    const uint64_t kick = board_.now_us() + static_cast<uint64_t>(config_.watchdog_ms) * 1000 / 4;
    if (kick < deadline) deadline = kick;
  }
  return deadline;
}

uint64_t Device::host_silence_deadline_us() const {
  if (config_.host_silence_us == 0 || config_.on_host_silence == HostSilence::kContinue) return UINT64_MAX;
  // Once acted on (paused, or aborting until the point in hand is done) there is nothing to watch.
  if (!scan_.active() || scan_.paused() || scan_.aborting()) return UINT64_MAX;
  return host_heard_us_ + config_.host_silence_us;
}

void Device::watch_host() {
  // A host that suspends the link has stopped listening, whatever the configuration says about
  // silence: the scan pauses at its next point (the points in hand are kept), a jog stops, and
  // the scan goes on when the host speaks again after its wake-up.
  if (board_.link_suspended()) {
    if (scan_.active() && !scan_.paused() && !scan_.aborting()) {
      scan_.set_paused(true);
      silence_paused_ = true;
    } else if (!scan_.active() && motion_.busy()) {
      motion_.stop();
    }
    return;
  }
  if (board_.now_us() < host_silence_deadline_us()) return;
  if (config_.on_host_silence == HostSilence::kAbort) {
    scan_.abort();
    motion_.stop();
    return;
  }
  scan_.set_paused(true);
  silence_paused_ = true;
}

bool Device::accept(const PointSample& point) {
  PointSample numbered = point;
  numbered.seq = next_seq_;
  if (!ring_.push(numbered)) return false;
  ++next_seq_;
  fit_.add(numbered);
  return true;
}

void Device::poll() {
  // A main loop that stops coming here (stuck in a wait, a fault that loops) stops kicking, and
  // the watchdog resets the board: no more steps, and status then says why it started.
  if (config_.watchdog_ms > 0) board_.watchdog_kick();
  receive();
  watch_motion();
  watch_host();
  if (jogging_ && !motion_.busy()) jogging_ = false;
  if (touching_ && !motion_.busy()) {
    touching_ = false;
    queue({Reply::kTouch, touch_request_, digitizer_FaultCode_FAULT_NONE, nullptr});
  }
  if (repeat_.poll()) {
    if (repeat_.failed()) {
      fault(repeat_.request_id(), digitizer_FaultCode_FAULT_PROBE_TIMEOUT, "repeatability: a reading or a move failed");
    } else {
      queue({Reply::kRepeatability, repeat_.request_id(), digitizer_FaultCode_FAULT_NONE, nullptr});
    }
  }
  scan_.poll(*this);
  transmit();
}

void Device::raise_alarm(digitizer_FaultCode code, const char* detail) {
  motion_.stop();
  // No current in the motors while in alarm: an e-stop or a crash leaves nothing driven.
  board_.enable_drivers(false);
  homing_.cancel();
  repeat_.cancel();
  jogging_ = false;
  touching_ = false;
  scan_.stop_faulted(code);
  // The position may no longer be where the steps say: home again after unlocking.
  homed_ = false;
  if (alarm_ && alarm_code_ == code) return;
  alarm_ = true;
  alarm_code_ = code;
  alarm_detail_ = detail;
  fault(0, code, detail);
}

// Pressed now and confirmed pressed by watch_motion (a spike alone does not refuse a command; an
// e-stop pressed within the confirming delay alarms the machine right after).
bool Device::estop_held() { return estop_confirmed_ && board_.read_pin(hal::Pin::kEstop); }

void Device::watch_motion() {
  // The e-stop read between moves is confirmed as the step interrupt confirms it: a second read at
  // least StepGenerator::kConfirmNs later, with no release seen between (a spike on the cable
  // must not alarm the machine and drop its homed position).
  if (board_.read_pin(hal::Pin::kEstop)) {
    const uint64_t now_us = board_.now_us();
    if (estop_seen_us_ == kNotSeen) estop_seen_us_ = now_us;
    if (now_us - estop_seen_us_ >= kEstopConfirmUs) {
      estop_confirmed_ = true;
      return raise_alarm(digitizer_FaultCode_FAULT_ESTOP, "e-stop pressed");
    }
  } else {
    estop_seen_us_ = kNotSeen;
    estop_confirmed_ = false;
  }
  const Trip trip = motion_.trip();
  if (trip == Trip::kEstop) return raise_alarm(digitizer_FaultCode_FAULT_ESTOP, "e-stop pressed");
  if (homing_.active()) {
    homing_.poll();
    if (homing_.done()) homed_ = true;
    if (homing_.failed()) {
      raise_alarm(digitizer_FaultCode_FAULT_NOT_HOMED, homing_.failure());
      homing_.cancel();
    }
    return;
  }
  if (trip == Trip::kLimitX || trip == Trip::kLimitY) {
    motion_.clear_trip();
    raise_alarm(digitizer_FaultCode_FAULT_HARD_LIMIT, trip == Trip::kLimitX ? "x min limit switch tripped" : "y min limit switch tripped");
  }
}

void Device::receive() {
  uint8_t chunk[64];
  for (int rounds = 0; rounds < 16; ++rounds) {
    const size_t got = board_.link_read(chunk, sizeof(chunk));
    if (got == 0) return;
    size_t offset = 0;
    while (offset < got) {
      size_t used = 0;
      const Status status = decoder_.feed(chunk + offset, got - offset, &used);
      offset += used;
      if (status == Status::kNeedMore) break;
      if (status != Status::kOk) continue;  // damaged frame: counted and skipped
      // A host is there again: a scan paused for its silence goes on.
      host_heard_us_ = board_.now_us();
      if (silence_paused_) {
        silence_paused_ = false;
        scan_.set_paused(false);
      }
      const bool deliver = link_.receive(decoder_.header(), board_.now_us());
      if (link_.take_restart()) restart_session();
      if (!deliver) continue;  // an ack, a duplicate, or a frame after a gap (it will come again)
      digitizer_Envelope message;
      if (decode_envelope(decoder_.payload(), decoder_.payload_size(), &message) != Status::kOk) {
        fault(0, digitizer_FaultCode_FAULT_BAD_FRAME, "message did not decode");
        continue;
      }
      handle(message);
    }
  }
}

void Device::handle(const digitizer_Envelope& message) {
  const uint32_t id = message.id;
  switch (message.which_body) {
    case digitizer_Envelope_host_hello_tag: {
      const digitizer_HostHello& host = message.body.host_hello;
      // The Hello still goes out after a fault, so the host can say what differs.
      if (host.protocol_version < digitizer_ProtocolVersion_PROTOCOL_VERSION ||
          host.min_protocol_version > digitizer_ProtocolVersion_PROTOCOL_VERSION) {
        fault(id, digitizer_FaultCode_FAULT_VERSION, "protocol versions cannot talk");
      } else if ((host.required_capabilities & ~config_.capabilities) != 0) {
        fault(id, digitizer_FaultCode_FAULT_UNSUPPORTED, "this device lacks a capability the host needs");
      }
      queue({Reply::kHello, id, digitizer_FaultCode_FAULT_NONE, nullptr});
      return;
    }
    case digitizer_Envelope_scan_request_tag: {
      if (alarm_) return fault(id, digitizer_FaultCode_FAULT_ALARM_LOCKED, "in alarm: unlock first");
      if (jogging_ || homing_.active() || repeat_.active() || touching_) return fault(id, digitizer_FaultCode_FAULT_BUSY, "the table is moving");
      if (config_.require_homing && !homed_) return fault(id, digitizer_FaultCode_FAULT_NOT_HOMED, "home the axes first");
      if (message.body.scan_request.probe != config_.probe) {
        return fault(id, digitizer_FaultCode_FAULT_UNSUPPORTED,
                     config_.probe == digitizer_ProbeType_PROBE_CALIPER_24BIT ? "this device's gauge is a 24-bit caliper"
                                                                              : "this device's gauge is a Digimatic indicator");
      }
      if (scan_.holding_point()) {
        return fault(id, digitizer_FaultCode_FAULT_BUSY, "an aborted scan's points wait in the device: resume it first");
      }
      if (scan_.finished()) scan_.acknowledge_finished();
      const char* reason = "";
      const digitizer_FaultCode code =
          scan_.start(message.body.scan_request, next_seq_, config_.default_feed_um_s, &reason);
      if (code != digitizer_FaultCode_FAULT_NONE) return fault(id, code, reason);
      line_first_seq_ = next_seq_;
      resend_done_ = false;
      fit_.begin(message.body.scan_request);
      Reply accepted{Reply::kAccepted, id, digitizer_FaultCode_FAULT_NONE, nullptr};
      accepted.first_seq = next_seq_;
      queue(accepted);
      return;
    }
    case digitizer_Envelope_command_tag:
      return handle_command(id, message.body.command);
    case digitizer_Envelope_resume_scan_tag:
      return resume_scan(id, message.body.resume_scan);
    case digitizer_Envelope_point_ack_tag: {
      const uint32_t acked = message.body.point_ack.seq;
      // Never free what was not sent: a wrong ack must not lose points.
      if (static_cast<int32_t>(acked - next_send_seq_) < 0) ring_.release_through(acked);
      return;
    }
    default:
      return fault(id, digitizer_FaultCode_FAULT_UNSUPPORTED, "not a host message");
  }
}

void Device::resume_scan(uint32_t id, const digitizer_ResumeScan& request) {
  const bool current = (scan_.active() || scan_.finished()) && scan_.scan_id() == request.scan_id;
  const bool done = !scan_.active() && !scan_.finished() && have_last_done_ && last_done_.scan_id == request.scan_id;
  if (request.scan_id == 0 || (!current && !done)) {
    return fault(id, digitizer_FaultCode_FAULT_BAD_REQUEST, "no such scan on this device (was it restarted?)");
  }
  const uint32_t oldest = ring_.empty() ? next_seq_ : ring_.at(0).seq;
  // 0: the host has none of this scan's points yet.
  const uint32_t next_seq = request.next_seq == 0 ? scan_.line_first_seq(0) : request.next_seq;
  if (static_cast<int32_t>(next_seq - oldest) < 0) {
    return fault(id, digitizer_FaultCode_FAULT_BAD_REQUEST, "points before the ring's oldest were acknowledged and freed");
  }
  if (static_cast<int32_t>(next_seq - next_seq_) > 0) {
    return fault(id, digitizer_FaultCode_FAULT_BAD_REQUEST, "the host claims points not yet measured");
  }
  // The host has everything before next_seq: free it and send from there.
  ring_.release_through(next_seq - 1);
  next_send_seq_ = next_seq;
  line_done_pending_ = false;
  if (!ring_.empty()) line_first_seq_ = scan_.line_first_seq(ring_.at(0).line);
  silence_paused_ = false;
  if (scan_.active()) scan_.set_paused(false);
  resend_done_ = done;
  Reply accepted{Reply::kAccepted, id, digitizer_FaultCode_FAULT_NONE, nullptr};
  accepted.first_seq = next_seq;
  queue(accepted);
}

bool Device::refuse_motion(uint32_t id) {
  if (alarm_) {
    fault(id, digitizer_FaultCode_FAULT_ALARM_LOCKED, "in alarm: unlock first");
  } else if (scan_.active() || motion_.busy() || homing_.active() || repeat_.active() || touching_) {
    fault(id, digitizer_FaultCode_FAULT_BUSY, "busy");
  } else if (config_.require_homing && !homed_) {
    fault(id, digitizer_FaultCode_FAULT_NOT_HOMED, "home the axes first");
  } else {
    return false;
  }
  return true;
}

bool Device::relative_target(const digitizer_Command& command, uint32_t default_feed_um_s, int32_t* x, int32_t* y,
                             uint32_t* rate) const {
  const int64_t per = config_.motion.nm_per_step;
  const int64_t tx = motion_.x_steps() + command.dx_nm / per;
  const int64_t ty = motion_.y_steps() + command.dy_nm / per;
  const uint32_t feed = command.feed_um_s != 0 ? command.feed_um_s : default_feed_um_s;
  *rate = static_cast<uint32_t>(static_cast<uint64_t>(feed) * 1000 / per);
  if (tx < INT32_MIN || tx > INT32_MAX || ty < INT32_MIN || ty > INT32_MAX) return false;
  *x = static_cast<int32_t>(tx);
  *y = static_cast<int32_t>(ty);
  return true;
}

void Device::handle_command(uint32_t id, const digitizer_Command& command) {
  switch (command.kind) {
    case digitizer_CommandKind_CMD_STATUS:
      return queue({Reply::kStatus, id, digitizer_FaultCode_FAULT_NONE, nullptr});
    case digitizer_CommandKind_CMD_ABORT:
      scan_.abort();
      motion_.stop();
      jogging_ = false;
      return queue({Reply::kAccepted, id, digitizer_FaultCode_FAULT_NONE, nullptr});
    case digitizer_CommandKind_CMD_PAUSE:
    case digitizer_CommandKind_CMD_RESUME:
      if (!scan_.active()) return fault(id, digitizer_FaultCode_FAULT_BAD_REQUEST, "no scan running");
      scan_.set_paused(command.kind == digitizer_CommandKind_CMD_PAUSE);
      return queue({Reply::kAccepted, id, digitizer_FaultCode_FAULT_NONE, nullptr});
    case digitizer_CommandKind_CMD_UNLOCK:
      if (estop_held()) return fault(id, digitizer_FaultCode_FAULT_ESTOP, "the e-stop is still pressed");
      motion_.clear_trip();
      alarm_ = false;
      alarm_code_ = digitizer_FaultCode_FAULT_NONE;
      board_.enable_drivers(true);
      return queue({Reply::kAccepted, id, digitizer_FaultCode_FAULT_NONE, nullptr});
    case digitizer_CommandKind_CMD_JOG: {
      if (refuse_motion(id)) return;
      int32_t x = 0, y = 0;
      uint32_t rate = 0;
      if (!relative_target(command, config_.default_feed_um_s, &x, &y, &rate) || motion_.move_to(x, y, rate) != Status::kOk) {
        return fault(id, digitizer_FaultCode_FAULT_SOFT_LIMIT, "jog target outside the table");
      }
      jogging_ = motion_.busy();
      return queue({Reply::kAccepted, id, digitizer_FaultCode_FAULT_NONE, nullptr});
    }
    case digitizer_CommandKind_CMD_TOUCH: {
      if ((config_.capabilities & digitizer_Capability_CAP_TOUCH_PROBE) == 0) return fault(id, digitizer_FaultCode_FAULT_UNSUPPORTED, "no touch probe fitted");
      if (refuse_motion(id)) return;
      int32_t x = 0, y = 0;
      uint32_t rate = 0;
      if (!relative_target(command, 1000, &x, &y, &rate) ||  // 1 mm/s unless told
          motion_.probe_to(x, y, rate, config_.touch_overtravel_steps) != Status::kOk) {
        return fault(id, digitizer_FaultCode_FAULT_BAD_REQUEST, "outside the table, or too fast to stop within the probe's overtravel");
      }
      touching_ = true;
      touch_request_ = id;
      return queue({Reply::kAccepted, id, digitizer_FaultCode_FAULT_NONE, nullptr});
    }
    case digitizer_CommandKind_CMD_REPEATABILITY:
      if (refuse_motion(id)) return;
      if (!repeat_.start(command.count, id)) return fault(id, digitizer_FaultCode_FAULT_BAD_REQUEST, "repeatability takes 2 to 64 readings");
      return queue({Reply::kAccepted, id, digitizer_FaultCode_FAULT_NONE, nullptr});
    case digitizer_CommandKind_CMD_PULL_FIT: {
      Reply reply{Reply::kFitResult, id, digitizer_FaultCode_FAULT_NONE, nullptr, command.fit_model};
      return queue(reply);
    }
    case digitizer_CommandKind_CMD_SET_CALIBRATION: {
      if (!command.has_calibration || command.calibration.version == 0) {
        return fault(id, digitizer_FaultCode_FAULT_BAD_REQUEST, "no calibration summary to keep");
      }
      calibration_ = command.calibration;
      has_calibration_ = true;
      uint8_t bytes[digitizer_CalibrationSummary_size];
      size_t size = 0;
      calibration_kept_ = encode_calibration_summary(calibration_, bytes, sizeof bytes, &size) == Status::kOk &&
                          board_.store_settings(bytes, size);
      return queue({Reply::kAccepted, id, digitizer_FaultCode_FAULT_NONE, nullptr});
    }
    case digitizer_CommandKind_CMD_HOME:
      // Allowed in alarm (homing is how a machine recovers its position), not with the e-stop.
      if (estop_held()) return fault(id, digitizer_FaultCode_FAULT_ESTOP, "the e-stop is pressed");
      if (scan_.active() || motion_.busy() || homing_.active()) return fault(id, digitizer_FaultCode_FAULT_BUSY, "busy");
      alarm_ = false;
      alarm_code_ = digitizer_FaultCode_FAULT_NONE;
      homed_ = false;
      motion_.clear_trip();
      board_.enable_drivers(true);
      homing_.start();
      return queue({Reply::kAccepted, id, digitizer_FaultCode_FAULT_NONE, nullptr});
    default:
      return fault(id, digitizer_FaultCode_FAULT_UNSUPPORTED, "unknown command");
  }
}

void Device::queue(Reply reply) {
  // A host flooding requests loses replies, never points.
  if (reply_count_ == sizeof(replies_) / sizeof(replies_[0])) return;
  replies_[reply_count_++] = reply;
}

bool Device::flush_tx() {
  for (;;) {
    while (tx_sent_ < tx_size_) {
      const size_t n = board_.link_write(tx_wire_ + tx_sent_, tx_size_ - tx_sent_);
      if (n == 0) return false;
      tx_sent_ += n;
    }
    tx_sent_ = tx_size_ = 0;
    if (!link_.next_frame(board_.now_us(), tx_wire_, sizeof(tx_wire_), &tx_size_)) return true;
  }
}

void Device::restart_session() {
  reply_count_ = 0;
  line_done_pending_ = false;
  // Everything the old host did not acknowledge with PointAck is still in the ring: send it again.
  next_send_seq_ = ring_.empty() ? next_seq_ : ring_.at(0).seq;
  if (!ring_.empty()) line_first_seq_ = scan_.line_first_seq(ring_.at(0).line);
  resend_done_ = false;
  tx_sent_ = tx_size_ = 0;
}

bool Device::send(const digitizer_Envelope& message) {
  // A full window (the host has not acknowledged its frames) waits: the caller tries again.
  // The message is encoded straight into the link's next slot: a payload buffer here was the
  // largest frame on the stack's deepest path.
  uint8_t* payload = link_.next_payload();
  if (payload == nullptr) return false;
  size_t payload_size = 0;
  if (encode_envelope(message, payload, Link::kPayloadCapacity, &payload_size) != Status::kOk) return false;
  if (link_.commit(payload_size, board_.now_us()) != Status::kOk) return false;
  flush_tx();
  return true;
}

bool Device::send_reply(const Reply& reply) {
  digitizer_Envelope message = digitizer_Envelope_init_zero;
  message.id = reply.request_id;
  switch (reply.kind) {
    case Reply::kHello: {
      message.which_body = digitizer_Envelope_hello_tag;
      digitizer_Hello& h = message.body.hello;
      h.protocol_version = digitizer_ProtocolVersion_PROTOCOL_VERSION;
      h.min_protocol_version = digitizer_ProtocolVersion_PROTOCOL_VERSION;
      set_string(h.firmware_version, config_.firmware_version);
      set_string(h.device_id, config_.device_id);
      set_string(h.board, config_.board);
      h.capabilities = config_.capabilities;
      h.has_table = true;
      h.table.has_x = h.table.has_y = h.table.has_z = true;
      const int64_t per = config_.motion.nm_per_step;
      h.table.x.max_nm = static_cast<int32_t>(config_.motion.x_max_steps * per);
      h.table.y.max_nm = static_cast<int32_t>(config_.motion.y_max_steps * per);
      h.table.z.min_nm = config_.gauge_min_nm;
      h.table.z.max_nm = config_.gauge_max_nm;
      h.gauge_resolution_nm = config_.gauge_resolution_nm;
      h.axis_resolution_nm = config_.motion.nm_per_step;
      h.point_ring_capacity = kPointRingCapacity;
      h.max_points_per_batch = kPointsPerBatch;
      break;
    }
    case Reply::kStatus: {
      message.which_body = digitizer_Envelope_status_tag;
      digitizer_Status& s = message.body.status;
      s.state = state();
      const int64_t per = config_.motion.nm_per_step;
      s.x_nm = static_cast<int32_t>(motion_.x_steps() * per);
      s.y_nm = static_cast<int32_t>(motion_.y_steps() * per);
      s.z_nm = scan_.last_z_nm();
      s.scan_id = scan_.scan_id();
      s.points_done = scan_.points_done();
      s.points_total = scan_.points_total();
      s.ring_used = static_cast<uint32_t>(ring_.size());
      s.alarm = alarm_code_;
      if (alarm_) set_string(s.alarm_detail, alarm_detail_);
      s.homed = homed_;
      s.reset_cause = reset_cause_name(board_.reset_cause());
      s.has_calibration = has_calibration_;
      if (has_calibration_) s.calibration = calibration_;
      s.calibration_kept = calibration_kept_;
      if (config_.stack_used_bytes != nullptr) {
        s.stack_used_bytes = config_.stack_used_bytes();
        s.stack_size_bytes = config_.stack_size_bytes;
      }
      break;
    }
    case Reply::kAccepted:
      message.which_body = digitizer_Envelope_accepted_tag;
      message.body.accepted.request_id = reply.request_id;
      message.body.accepted.first_seq = reply.first_seq;
      break;
    case Reply::kFitResult:
      // Solved when it is sent, from every point stored so far.
      message.which_body = digitizer_Envelope_fit_result_tag;
      fit_.result(reply.fit_model, !scan_.active(), &message.body.fit_result);
      break;
    case Reply::kTouch: {
      message.which_body = digitizer_Envelope_touch_result_tag;
      digitizer_TouchResult& t = message.body.touch_result;
      const int64_t per = config_.motion.nm_per_step;
      t.touched = motion_.touched();
      t.x_nm = static_cast<int32_t>(motion_.touch_x_steps() * per);
      t.y_nm = static_cast<int32_t>(motion_.touch_y_steps() * per);
      t.stop_x_nm = static_cast<int32_t>(motion_.x_steps() * per);
      t.stop_y_nm = static_cast<int32_t>(motion_.y_steps() * per);
      break;
    }
    case Reply::kRepeatability:
      message.which_body = digitizer_Envelope_repeatability_tag;
      message.body.repeatability = repeat_.result();
      break;
    case Reply::kLineDone:
      message.which_body = digitizer_Envelope_line_done_tag;
      message.body.line_done = line_done_;
      break;
    case Reply::kScanDone:
      message.which_body = digitizer_Envelope_scan_done_tag;
      message.body.scan_done = last_done_;
      break;
    case Reply::kFault:
      message.which_body = digitizer_Envelope_fault_tag;
      message.body.fault.code = reply.code;
      message.body.fault.request_id = reply.request_id;
      set_string(message.body.fault.detail, reply.detail);
      break;
  }
  return send(message);
}

void Device::adapt_batch_size() {
  const uint32_t resent = link_.counters().retransmitted;
  if (resent != seen_retransmits_) {
    seen_retransmits_ = resent;
    batch_points_ = static_cast<uint16_t>(batch_points_ > 1 ? batch_points_ / 2 : 1);
    clean_batches_ = 0;
  } else if (batch_points_ < kPointsPerBatch && ++clean_batches_ >= kCleanBatchesToGrow) {
    batch_points_ = static_cast<uint16_t>(batch_points_ * 2 < kPointsPerBatch ? batch_points_ * 2 : kPointsPerBatch);
    clean_batches_ = 0;
  }
}

bool Device::send_points() {
  const size_t held = ring_.size();
  size_t offset = first_unsent_offset();
  if (offset >= held) return false;
  digitizer_Envelope message = digitizer_Envelope_init_zero;
  message.which_body = digitizer_Envelope_points_tag;
  digitizer_PointBatch& batch = message.body.points;
  const PointSample& first = ring_.at(offset);
  point_batch_begin(&batch, first.seq, first.line);
  bool line_end = false;
  for (; offset < held && !line_end && point_batch_size(batch) < batch_points_; ++offset) {
    if (point_batch_append(&batch, ring_.at(offset)) != Status::kOk) break;
    line_end = (ring_.at(offset).flags & digitizer_PointFlag_POINT_LINE_END) != 0;
  }
  const size_t count = point_batch_size(batch);
  // Send a full batch, a line's end, or whatever waits when the scan is over or it is old.
  const bool due = count >= batch_points_ || line_end || !scan_.active() ||
                   board_.now_us() >= first.t_us + kBatchMaxAgeUs;
  if (!due) return false;
  if (!send(message)) return false;
  adapt_batch_size();
  next_send_seq_ = first.seq + static_cast<uint32_t>(count);
  if (line_end) {
    line_done_ = digitizer_LineDone_init_zero;
    line_done_.line = first.line;
    line_done_.last_seq = next_send_seq_ - 1;
    line_done_.points = next_send_seq_ - line_first_seq_;
    line_first_seq_ = next_send_seq_;
    line_done_pending_ = true;
  }
  return true;
}

void Device::transmit() {
  for (int rounds = 0; rounds < 8; ++rounds) {
    if (!flush_tx()) return;
    if (reply_count_ > 0) {
      if (!send_reply(replies_[0])) return;
      for (size_t i = 1; i < reply_count_; ++i) replies_[i - 1] = replies_[i];
      --reply_count_;
      continue;
    }
    if (line_done_pending_) {
      Reply line_done{};
      line_done.kind = Reply::kLineDone;
      if (!send_reply(line_done)) return;
      line_done_pending_ = false;
      continue;
    }
    if (send_points()) continue;
    // A scan that ended: its ScanDone once every point is on the wire (after its fault, if any).
    if (scan_.finished() && !scan_.holding_point() && next_send_seq_ == next_seq_ && !resend_done_) {
      last_done_ = digitizer_ScanDone_init_zero;
      last_done_.scan_id = scan_.scan_id();
      last_done_.reason = scan_.end_reason();
      last_done_.points = scan_.points_done();
      last_done_.lines = scan_.lines_done();
      last_done_.duration_us = scan_.duration_us();
      have_last_done_ = true;
      if (scan_.end_reason() == digitizer_ScanEnd_SCAN_FAULTED && !alarm_) {
        board_.enable_drivers(false);
        alarm_ = true;
        alarm_code_ = scan_.fault();
        fault(0, scan_.fault(), "scan stopped by a fault");
      }
      resend_done_ = true;  // sent below, once the queued fault is out
      continue;
    }
    // ScanDone of the scan that just ended, or again for a resumed host that missed it.
    if (resend_done_ && next_send_seq_ == next_seq_) {
      Reply scan_done{};
      scan_done.kind = Reply::kScanDone;
      if (!send_reply(scan_done)) return;
      resend_done_ = false;
      if (scan_.finished()) scan_.acknowledge_finished();
      continue;
    }
    return;
  }
}

DeviceConfig hardware_device_config(bool caliper) {
  DeviceConfig config;
  config.firmware_version = DIGITIZER_VERSION;
  if (caliper) {
    config.probe = digitizer_ProbeType_PROBE_CALIPER_24BIT;
    config.gauge_resolution_nm = 10000;
  }
  config.capabilities = (caliper ? digitizer_Capability_CAP_CALIPER_24BIT : digitizer_Capability_CAP_DIGIMATIC) |
                        digitizer_Capability_CAP_DEVICE_FIT | digitizer_Capability_CAP_RESUME |
                        digitizer_Capability_CAP_HOMING | digitizer_Capability_CAP_TOUCH_PROBE |
                        digitizer_Capability_CAP_CALIBRATION_SUMMARY | digitizer_Capability_CAP_FLY_SCAN;
  config.require_homing = true;
  // A hung main loop resets the board (the steps stop; the drivers' enable line falls back to its
  // reset state), and status says so after.
  config.watchdog_ms = 1000;
  return config;
}

}  // namespace dg
