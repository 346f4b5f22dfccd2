// The device application: link I/O, the hello exchange, commands, the scan and the point ring.
#pragma once
#include <cstddef>
#include <cstdint>

#include "common/link/frame.h"
#include "common/link/reliable_link.h"
#include "common/proto/messages.h"
#include "common/proto/point_batch.h"
#include "digitizer.pb.h"
#include "firmware/core/device_fit.h"
#include "firmware/core/caliper24.h"
#include "firmware/core/digimatic_reader.h"
#include "firmware/core/homing.h"
#include "firmware/core/point_ring.h"
#include "firmware/core/repeatability.h"
#include "firmware/core/scan_engine.h"
#include "firmware/core/step_generator.h"
#include "firmware/hal/board.h"

namespace dg {

// A board with little RAM builds the core with smaller figures (see hw/boards/stm32f411): the ring
// holds the points the host has not yet confirmed (32 bytes each), the window is how many frames
// may be in flight unacknowledged (a power of two), and a frame's payload is at most
// DG_LINK_SLOT_PAYLOAD bytes (each frame in flight keeps that many, plus 16).
#ifndef DG_POINT_RING_CAPACITY
#define DG_POINT_RING_CAPACITY 128
#endif
#ifndef DG_LINK_WINDOW
#define DG_LINK_WINDOW 4
#endif
#ifndef DG_LINK_SLOT_PAYLOAD
#define DG_LINK_SLOT_PAYLOAD kFrameMaxPayload
#endif
constexpr size_t kPointRingCapacity = DG_POINT_RING_CAPACITY;
constexpr size_t kLinkWindow = DG_LINK_WINDOW;
constexpr size_t kLinkSlotPayload = DG_LINK_SLOT_PAYLOAD;
static_assert(kDeviceReplyMaxSize <= kLinkSlotPayload, "every reply must fit one of the device's frames");
// Points per batch: as many as the protocol allows and a frame holds.
constexpr size_t kPointsPerBatch = point_batch_envelope_max(kMaxPointsPerBatch) <= kLinkSlotPayload
                                       ? kMaxPointsPerBatch
                                       : (kLinkSlotPayload - point_batch_envelope_max(0)) / (point_batch_envelope_max(1) - point_batch_envelope_max(0));
static_assert(kPointsPerBatch >= 1 && point_batch_envelope_max(kPointsPerBatch) <= kLinkSlotPayload,
              "a frame must hold a batch of at least one point");
// A partly filled batch goes out after this long, so a slow scan still streams.
constexpr uint64_t kBatchMaxAgeUs = 1000000;
// An unacknowledged frame is sent again after this long.
constexpr uint32_t kRetransmitUs = 50000;

// What a scan does when the host has sent nothing (not even an acknowledgement) for
// DeviceConfig::host_silence_us. Points are never lost either way: a full ring stops the scan.
enum class HostSilence : uint8_t {
  kContinue,  // scan on until the ring is full
  kPause,     // stop where it is; the next frame from a host continues the scan
  kAbort,     // end the scan (ScanDone, SCAN_ABORTED) and leave the table where it is
};

struct DeviceConfig {
  MotionConfig motion{};
  DigimaticTiming gauge{};
  CaliperTiming caliper{};
  // The gauge wired to the gauge port; scans that ask for another are refused.
  digitizer_ProbeType probe = digitizer_ProbeType_PROBE_DIGIMATIC;
  ScanLimits scan{};
  const char* firmware_version = "0.1.0";
  const char* device_id = "DG-0000";
  const char* board = "unknown";
  uint32_t capabilities = 0;
  uint32_t gauge_resolution_nm = 1000;
  int32_t gauge_min_nm = 0;
  int32_t gauge_max_nm = 25000000;
  uint32_t default_feed_um_s = 10000;
  // An unacknowledged frame is sent again after this long. The simulator's virtual time runs far
  // faster than the host's real time, so it sets a longer one.
  uint32_t retransmit_us = kRetransmitUs;
  // A host that sends nothing for this long during a scan is taken as gone (0: never). The host
  // sends at least a status request every 300 ms while it listens.
  uint32_t host_silence_us = 2000000;
  HostSilence on_host_silence = HostSilence::kPause;
  // Refuse scans and jogs until the axes are homed (a real machine; the simulator's table starts
  // at its origin).
  bool require_homing = false;
  // Touch-trigger probing: the stylus's allowed travel after it triggers, steps (the probing feed
  // must brake within it).
  uint32_t touch_overtravel_steps = 400;
  // The stack's size and its high-water mark since reset (stack painting), for `status`; a board
  // that cannot measure it leaves these empty.
  uint32_t (*stack_used_bytes)() = nullptr;
  uint32_t stack_size_bytes = 0;
  // The board's watchdog, started at begin() and kicked by every pass of the main loop, which then
  // never sleeps longer than a quarter of it (0: not started).
  uint32_t watchdog_ms = 0;
};

// A controller on real hardware: the reference table's motion (the MotionConfig defaults), the
// probe its gauge port carries (a Digimatic gauge, or a 24-bit caliper at 0.01 mm), the
// capabilities a real board has, and homing required before anything moves (after power-up the
// firmware cannot know where the table is). The caller names the device and the board.
DeviceConfig hardware_device_config(bool caliper);

class Device : private PointSink {
 public:
  Device(hal::Board& board, const DeviceConfig& config);

  // Attaches interrupts; call once.
  void begin();
  // Does all work possible now: reads the link, advances the scan, sends.
  void poll();
  // When poll() must next run even if no interrupt or byte arrives.
  uint64_t next_deadline_us() const;
  // poll() and wait() until the board shuts down.
  void run();

  digitizer_DeviceState state() const;
  size_t ring_used() const { return ring_.size(); }

 private:
  struct Reply {
    // kLineDone and kScanDone send line_done_ and last_done_: built here rather than in transmit(),
    // whose frame would otherwise hold a second message under send_reply's on the deepest path.
    enum Kind : uint8_t { kHello, kStatus, kAccepted, kFault, kFitResult, kRepeatability, kTouch, kLineDone, kScanDone } kind;
    uint32_t request_id;
    digitizer_FaultCode code;
    const char* detail;
    digitizer_DeviceFitModel fit_model = digitizer_DeviceFitModel_DEVICE_FIT_BEZIER;  // kFitResult
    uint32_t first_seq = 0;  // kAccepted of a scan or resume: its first point
  };

  bool accept(const PointSample& point) override;
  uint32_t room() const override { return static_cast<uint32_t>(ring_.capacity() - ring_.size()); }
  void receive();
  void handle(const digitizer_Envelope& message);
  void handle_command(uint32_t id, const digitizer_Command& command);
  void resume_scan(uint32_t id, const digitizer_ResumeScan& request);
  // Safety: the e-stop input, tripped limit switches and homing's end.
  void watch_motion();
  // The e-stop pressed now and confirmed pressed by watch_motion (refuses unlock and home).
  bool estop_held();
  void raise_alarm(digitizer_FaultCode code, const char* detail);
  // Queues the fault and returns true when the table may not move now (alarm, busy, not homed).
  bool refuse_motion(uint32_t id);
  // A command's relative target (dx_nm, dy_nm) in steps and its feed in steps/s; false when the
  // target does not fit the step counter.
  bool relative_target(const digitizer_Command& command, uint32_t default_feed_um_s, int32_t* x, int32_t* y,
                       uint32_t* rate) const;
  // Applies the host-silence policy to a running scan.
  void watch_host();
  // When watch_host() must next look (UINT64_MAX: not now).
  uint64_t host_silence_deadline_us() const;
  void queue(Reply reply);
  void fault(uint32_t id, digitizer_FaultCode code, const char* detail) {
    queue({Reply::kFault, id, code, detail});
  }
  // Writes what the wire takes: the rest of the current frame, then the link's due frames.
  bool flush_tx();
  // A new host session: its replies and unconfirmed points are sent again from the ring.
  void restart_session();
  bool send(const digitizer_Envelope& message);
  void transmit();
  bool send_reply(const Reply& reply);
  bool send_points();
  // Shrinks or grows batch_points_ from the link's retransmissions since the last batch.
  void adapt_batch_size();
  // Ring index of the first point not yet sent (== ring size when all are sent).
  size_t first_unsent_offset() const;

  hal::Board& board_;
  DeviceConfig config_;
  StepGenerator motion_;
  DigimaticReader gauge_;
  Caliper24Reader caliper_;
  ScanEngine scan_;
  DeviceFit fit_;
  PointRing<kPointRingCapacity> ring_;
  // Room for the host's requests only: 556 bytes for any frame was the largest buffer after the fit's.
  SizedFrameDecoder<kHostEnvelopeMaxSize> decoder_;
  uint32_t next_seq_ = 1;        // next point sequence number
  uint32_t next_send_seq_ = 1;   // first point not yet sent
  uint32_t line_first_seq_ = 1;  // first point of the line being sent
  // Points per batch, halved whenever the link has resent a frame and doubled again after
  // kCleanBatchesToGrow batches without one: on a line that damages bytes, a short frame gets
  // through where a full one almost never does.
  static constexpr uint16_t kCleanBatchesToGrow = 16;
  uint16_t batch_points_ = kPointsPerBatch;
  uint16_t clean_batches_ = 0;
  uint32_t seen_retransmits_ = 0;  // the link's retransmission count when last looked at
  // The flags together: scattered among wider members each took a word or more of padding.
  bool line_done_pending_ = false;
  bool alarm_ = false;
  bool jogging_ = false;
  bool homed_ = false;
  bool estop_confirmed_ = false;  // seen twice: the alarm is raised, no more looks needed
  bool touching_ = false;          // a CMD_TOUCH move is running
  bool silence_paused_ = false;   // paused by watch_host(), not by CMD_PAUSE
  bool have_last_done_ = false;
  bool resend_done_ = false;  // last_done_ is due on the wire
  bool has_calibration_ = false;   // calibration_ was set (now or, where the board stores it, before)
  bool calibration_kept_ = false;  // and the board stored it through a power-off
  digitizer_CalibrationSummary calibration_ = digitizer_CalibrationSummary_init_zero;
  digitizer_LineDone line_done_ = digitizer_LineDone_init_zero;
  digitizer_FaultCode alarm_code_ = digitizer_FaultCode_FAULT_NONE;
  const char* alarm_detail_ = "";  // a string literal: the alarm's reason, for Status
  Homing homing_;
  // When the e-stop was first seen pressed between moves, for its confirming read.
  static constexpr uint64_t kNotSeen = UINT64_MAX;
  static constexpr uint64_t kEstopConfirmUs = StepGenerator::kConfirmNs / 1000;
  uint64_t estop_seen_us_ = kNotSeen;
  RepeatabilityRun repeat_;
  uint32_t touch_request_ = 0;
  uint64_t host_heard_us_ = 0;    // device time of the last good frame from a host
  // The last scan's ScanDone, kept to be sent again when a resumed host asks for a finished scan.
  digitizer_ScanDone last_done_ = digitizer_ScanDone_init_zero;
  using Link = ReliableLink<kLinkWindow, kLinkSlotPayload>;
  Link link_;
  uint8_t tx_wire_[Link::kWireCapacity] = {};
  size_t tx_size_ = 0, tx_sent_ = 0;
  Reply replies_[8] = {};
  size_t reply_count_ = 0;
};

}  // namespace dg
