// Scan engine: walks the grid of a ScanRequest (raster or serpentine), moves, settles,
// reads the gauge and hands each point to a sink that may refuse it when full.
#pragma once
#include <cstdint>

#include "common/proto/point_batch.h"
#include "common/status.h"
#include "digitizer.pb.h"
#include "firmware/core/probe.h"
#include "firmware/core/step_generator.h"

namespace dg {

// Receives points in order; returns false when it has no room (the scan waits).
class PointSink {
 public:
  virtual bool accept(const PointSample& point) = 0;
  // How many more points it would take now (a scan on the fly flies a line again only with room).
  virtual uint32_t room() const { return UINT32_MAX; }

 protected:
  ~PointSink() = default;
};

// The readings a reference reading (ScanRequest.reference_every_lines) averages at least.
constexpr uint32_t kReferenceSamples = 4;

struct ScanLimits {
  uint32_t max_points = 4000000;
  uint32_t max_samples_per_point = 16;
  uint32_t probe_retries = 3;   // extra reads after a failed one, per sample
  uint32_t max_settle_reads = 8;  // readings spent waiting for two that agree
};

class ScanEngine {
 public:
  enum class Phase : uint8_t {
    kIdle, kApproaching, kMoving, kSettling, kReading, kEmitting, kPaused, kFinished,
    kRunUp,   // on the fly: to the line's start, a run-up before its extent
    kTiming,  // on the fly, once: one reading at rest times the gauge's cycle, which sets the feed
    kFlying,  // on the fly: the line at constant feed, readings back to back
  };

  ScanEngine(hal::Board& board, StepGenerator& motion, Probe& gauge, ScanLimits limits);

  // Validates and starts a scan; points are numbered from `first_seq`. On a
  // refusal returns the fault code and a one-line reason.
  digitizer_FaultCode start(const digitizer_ScanRequest& request, uint32_t first_seq,
                            uint32_t default_feed_um_s, const char** reason);
  // Does whatever can be done now without blocking.
  void poll(PointSink& sink);
  uint64_t deadline_us() const;

  void abort();
  // Ends a running scan at once as faulted (a hard limit, the e-stop): no further move or reading.
  void stop_faulted(digitizer_FaultCode code) {
    if (active()) finish(digitizer_ScanEnd_SCAN_FAULTED, code);
  }
  void set_paused(bool paused) { paused_ = paused; }
  bool paused() const { return paused_; }
  bool aborting() const { return abort_requested_; }

  bool active() const { return phase_ != Phase::kIdle && phase_ != Phase::kFinished; }
  bool finished() const { return phase_ == Phase::kFinished; }
  void acknowledge_finished() { phase_ = Phase::kIdle; }
  // An aborted scan's last measured point still waits for room in the ring: its ScanDone waits too.
  bool holding_point() const { return holding_ || fly_held_; }
  digitizer_ScanEnd end_reason() const { return end_; }
  digitizer_FaultCode fault() const { return fault_; }
  uint32_t scan_id() const { return request_.scan_id; }
  uint32_t points_done() const { return points_done_; }
  // The grid's points and the reference readings (ScanRequest.reference_every_lines); on the fly,
  // the points the lines would hold at step_x_nm apart (the gauge's cycle decides).
  uint32_t points_total() const { return count_x_ * count_y_ + references_total(); }
  uint32_t lines_done() const { return lines_done_; }
  // Sequence number of the first point of line `line`. On a grid every line has the same length and
  // a reference reading ends every reference_every_lines-th line; on the fly the engine remembers
  // the last kFlyLinesKept lines' (older lines' points have long left the ring).
  uint32_t line_first_seq(uint32_t line) const;
  bool flying() const { return fly_; }
  // On the fly: the gauge's cycle measured at rest (us) and the feed it set (steps/s).
  uint32_t gauge_cycle_us() const { return cycle_us_; }
  uint32_t fly_rate_steps_s() const { return fly_rate_steps_s_; }
  uint64_t duration_us() const { return finished_us_ - started_us_; }
  int32_t last_z_nm() const { return last_z_nm_; }

 private:
  void begin_point();
  // Moves to the scan's first point to read it again (a reference reading).
  void begin_reference();
  // Moves to (x_nm, y_nm), by way of the single-direction approach, and starts the point's reading.
  void begin_move(int64_t x_nm, int64_t y_nm);
  // A reference reading follows grid line `line`: after every reference_every_lines-th and the last.
  bool reference_after(uint32_t line) const {
    const uint32_t every = request_.reference_every_lines;
    return every > 0 && ((line + 1) % every == 0 || line + 1 == count_y_);
  }
  uint32_t references_total() const { return references_total_; }
  void end_line();
  // A good reading arrived: settle, sample, or finish the point; true when the point is done.
  bool take_reading(int64_t value_nm);
  int64_t point_value() const;
  void finish(digitizer_ScanEnd why, digitizer_FaultCode fault);
  // The pending point went into the ring: count it and step the grid index.
  void count_emitted();
  int32_t to_steps(int64_t nm) const;
  // On the fly (fly_scan.cpp): checks a request for flying; starts a line; runs the line's phases.
  const char* fly_refusal(const digitizer_ScanRequest& request) const;
  void begin_fly_line();
  void poll_fly(PointSink& sink);
  void start_fly_reading();
  // Whether the flight, from its last request to `to_steps`, passed more than two steps of the
  // extent without a reading; if so marks the gap (fly_gap_, fly_gap_from_).
  bool passed_readings_by(int32_t to_steps);
  void take_fly_reading(int64_t value_nm);
  // Offers pending_ to the sink; false (and fly_waiting_) while it has no room.
  bool offer_fly_point(PointSink& sink);
  // The held point becomes pending_ (numbered next, with `flags` added); it is held no longer.
  void pend_held_point(uint32_t flags) {
    pending_ = fly_point_;
    pending_.seq = next_seq_;
    pending_.flags |= flags;
    fly_held_ = false;
  }
  // The held point goes out as the line's last; then the next line, or the end. A line with a gap
  // is flown again first, once the sink has room.
  void end_fly_line(PointSink& sink);
  // Moves to the line's run-up (the same line again when `again`).
  void begin_fly_run(bool again);

  hal::Board& board_;
  StepGenerator& motion_;
  Probe& gauge_;
  ScanLimits limits_;
  digitizer_ScanRequest request_ = digitizer_ScanRequest_init_zero;
  Phase phase_ = Phase::kIdle;
  bool paused_ = false;
  bool abort_requested_ = false;
  bool holding_ = false;  // finished with pending_ not yet in the ring
  bool reference_due_ = false;  // a line is done and its reference reading comes next
  bool in_reference_ = false;   // the point being measured is a reference reading
  uint32_t count_x_ = 0, count_y_ = 0;
  uint32_t references_total_ = 0;  // ScanGrid::references
  uint32_t ix_ = 0, iy_ = 0;  // grid index of the current point (ix along the line)
  uint32_t rate_steps_s_ = 0;
  uint32_t next_seq_ = 0;
  uint32_t first_seq_ = 0;
  uint32_t points_done_ = 0, lines_done_ = 0;
  uint64_t settle_until_us_ = 0;
  uint64_t started_us_ = 0, finished_us_ = 0;
  // Samples of the current point.
  uint32_t samples_taken_ = 0, retries_left_ = 0;
  int64_t samples_nm_[16] = {};   // the current point's samples (max_samples_per_point at most)
  uint32_t settle_reads_ = 0;     // readings taken while settling (0: not settling)
  int32_t target_x_ = 0, target_y_ = 0;  // the point's position, steps (kApproaching goes past it first)
  int64_t previous_nm_ = 0;       // the last settling reading
  bool spread_retried_ = false;
  int64_t z_sum_nm_ = 0;
  uint32_t point_flags_ = 0;
  PointSample pending_{};
  int32_t last_z_nm_ = 0;
  digitizer_ScanEnd end_ = digitizer_ScanEnd_SCAN_COMPLETED;
  digitizer_FaultCode fault_ = digitizer_FaultCode_FAULT_NONE;
  // On the fly.
  static constexpr uint32_t kFlyLinesKept = 8;
  // Room the sink must have before a line with a gap is flown again (a quarter of the device's ring).
  static constexpr uint32_t kFlyRoomToFlyAgain = 32;
  bool fly_ = false;
  bool fly_reading_ = false;   // a reading runs; it was requested at fly_req_us_ at fly_req_x_
  bool fly_held_ = false;      // fly_point_ waits for the next reading or the line's end
  bool fly_waiting_ = false;   // pending_ waits for room in the ring (no new reading meanwhile)
  bool fly_first_ = true;      // the line's next point is its first
  // The ring was full long enough mid-line for the table to pass readings by: the rest of the line
  // is flown again, its points taken only beyond fly_gap_from_ (steps, the last point kept).
  bool fly_gap_ = false;
  bool fly_again_ = false;     // this flight of the line continues after fly_gap_from_
  bool fly_requested_ = false; // this flight has requested a reading (fly_req_x_ is its last)
  int32_t fly_gap_from_ = 0;
  int8_t fly_dir_ = 1;
  int32_t fly_lo_steps_ = 0, fly_hi_steps_ = 0;  // the scan's extent along x
  int32_t fly_runup_steps_ = 0;
  uint32_t fly_rate_steps_s_ = 0;
  uint32_t cycle_us_ = 0;
  uint32_t fly_failures_ = 0;  // failed readings in a row
  uint32_t plunger_um_s_ = 0;
  int32_t fly_req_x_ = 0;
  uint64_t fly_req_us_ = 0;
  PointSample fly_point_{};
  // This flight's last reading within the extent, kept or short of its gap: the lift check's
  // predecessor.
  bool fly_prev_ = false;
  int32_t fly_prev_z_nm_ = 0;
  uint64_t fly_prev_us_ = 0;
  uint32_t fly_first_seq_[kFlyLinesKept] = {};
};


}  // namespace dg
