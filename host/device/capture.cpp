// Capture loop: store first, then acknowledge, so the device frees only what is on disk.
#include "host/device/capture.h"

#include <algorithm>
#include <chrono>
#include <thread>

#include "common/proto/scan_grid.h"

namespace dg::host {

namespace {

using Clock = std::chrono::steady_clock;

int64_t ms_since(Clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t).count();
}

// Sequence numbers wrap at 2^32; compare them as a window.
bool seq_before(uint32_t a, uint32_t b) { return static_cast<int32_t>(a - b) < 0; }

class Capture {
 public:
  Capture(Session& session, ScanSink& file, const CaptureOptions& options, const digitizer_ScanRequest& request)
      : session_(session), file_(file), options_(options), scan_id_(request.scan_id) {
    ScanGrid grid;
    if (scan_grid(request, &grid)) progress_.points_total = static_cast<uint32_t>(grid.readings());
  }

  // Continues after what the file holds: asks the device for the points after its last one.
  CaptureResult resume(const ScanData& stored) {
    result_.points = progress_.points = static_cast<uint32_t>(stored.points.size());
    result_.lines = progress_.lines = static_cast<uint32_t>(stored.lines.size());
    expected_seq_ = stored.points.empty() ? 0 : stored.points.back().seq + 1;
    if (!stored.lines.empty()) {
      have_last_line_ = true;
      last_line_ = stored.lines.back().line;
    }
    if (!stored.points.empty()) {
      const PointSample& last = stored.points.back();
      tail_line_ = last.line;
      tail_line_end_ = (last.flags & digitizer_PointFlag_POINT_LINE_END) != 0;
      tail_line_points_ = 0;
      for (auto p = stored.points.rbegin(); p != stored.points.rend() && p->line == last.line; ++p) ++tail_line_points_;
      have_tail_ = true;
      complete_last_line();
    }
    return run(send_resume(), true);
  }

  CaptureResult run(uint32_t request_id, bool resuming) {
    request_id_ = request_id;
    resuming_ = resuming;
    // When the last new message came, when the last whole frame came (of any kind), and how many
    // damaged frames had arrived by the last message.
    auto last_heard = Clock::now();
    auto last_frame = last_heard;
    uint32_t damaged_at_message = session_.frames_damaged();
    digitizer_Envelope message;
    for (;;) {
      try {
        if (stop_ == Stop::kNone && options_.stop_requested && options_.stop_requested()) request_pause();
        if (stop_ == Stop::kPaused && ms_since(quiet_since_) >= 200) break;
        if (stop_ != Stop::kNone && ms_since(stop_asked_) >= 2000) break;
        // With points waiting for their acknowledgement, wait only briefly: a device whose ring is
        // full sends nothing until they are acknowledged.
        const int wait_ms = unacknowledged_ > 0 ? std::min(5, options_.heartbeat_ms)
                            : stop_ == Stop::kNone ? options_.heartbeat_ms : 50;
        if (!session_.receive(&message, wait_ms)) {
          if (unacknowledged_ > 0) {
            acknowledge();
            continue;
          }
          if (stop_ != Stop::kNone) continue;
          if (session_.frames_whole() != frames_seen_) {
            frames_seen_ = session_.frames_whole();
            last_frame = Clock::now();
          }
          const int64_t silent_ms = ms_since(last_frame);
          if (silent_ms >= options_.silence_timeout_ms) {
            throw DeviceError(session_.device_name() + ": device silent for " + std::to_string(silent_ms) +
                              " ms after " + std::to_string(result_.points) + " points" + damage_since(damaged_at_message) +
                              "; they are in " + file_.path());
          }
          const int64_t stuck_ms = ms_since(last_heard);
          if (stuck_ms >= options_.no_progress_timeout_ms) {
            throw DeviceError(session_.device_name() + ": the link brought nothing new for " + std::to_string(stuck_ms / 1000) +
                              " s after " + std::to_string(result_.points) + " points" + damage_since(damaged_at_message) +
                              "; they are in " + file_.path());
          }
          // A slow scan (long settling, many samples) may have nothing to say: ask for a sign of life.
          send_command(digitizer_CommandKind_CMD_STATUS);
          continue;
        }
        last_heard = last_frame = quiet_since_ = Clock::now();
        damaged_at_message = session_.frames_damaged();
        if (handle(message)) return result_;
      } catch (const TransportError& e) {
        reconnect(e);
        last_heard = last_frame = Clock::now();
        damaged_at_message = session_.frames_damaged();
      }
    }
    // Stopped on request: everything that arrived is stored and acknowledged.
    acknowledge();
    file_.sync();
    session_.flush(1000);
    result_.interrupted = true;
    return result_;
  }

 private:
  enum class Stop { kNone, kAsked, kPaused };

  // ", while 12 damaged frames arrived (check the cable)" when frames arrived damaged since the
  // last message, else "".
  std::string damage_since(uint32_t damaged_before) const {
    const uint32_t damaged = session_.frames_damaged() - damaged_before;
    if (damaged == 0) return "";
    return ", while " + std::to_string(damaged) + " damaged frame" + (damaged == 1 ? "" : "s") +
           " arrived (check the cable)";
  }

  uint32_t send_command(digitizer_CommandKind kind) {
    digitizer_Envelope command = digitizer_Envelope_init_zero;
    command.which_body = digitizer_Envelope_command_tag;
    command.body.command.kind = kind;
    return session_.send(command);
  }

  void request_pause() {
    stop_ = Stop::kAsked;
    stop_asked_ = Clock::now();
    pause_id_ = send_command(digitizer_CommandKind_CMD_PAUSE);
  }

  // The link broke (or the host stopped) between a line's last point and its LineDone: the device,
  // asked for the points after it, will not send that LineDone again, so it is written from the
  // points stored.
  void complete_last_line() {
    if (!have_tail_ || !tail_line_end_) return;
    if (have_last_line_ && !seq_before(last_line_, tail_line_)) return;
    digitizer_Envelope done = digitizer_Envelope_init_zero;
    done.which_body = digitizer_Envelope_line_done_tag;
    done.body.line_done.line = tail_line_;
    done.body.line_done.points = tail_line_points_;
    done.body.line_done.last_seq = expected_seq_ - 1;
    store_line_done(done);
  }

  // Stores a line's end once (lines only go up: one sent again after a reconnect is skipped).
  void store_line_done(const digitizer_Envelope& message) {
    if (have_last_line_ && !seq_before(last_line_, message.body.line_done.line)) return;
    have_last_line_ = true;
    last_line_ = message.body.line_done.line;
    file_.append(message);
    if (unacknowledged_ > 0) acknowledge();  // syncs the line's end too
    else file_.sync();
    ++result_.lines;
    progress_.lines = result_.lines;
  }

  uint32_t send_resume() {
    digitizer_Envelope resume = digitizer_Envelope_init_zero;
    resume.which_body = digitizer_Envelope_resume_scan_tag;
    resume.body.resume_scan.scan_id = scan_id_;
    resume.body.resume_scan.next_seq = expected_seq_;
    return session_.send(resume);
  }

  // The link broke: reach the device again and continue from the last stored point.
  void reconnect(const TransportError& error) {
    file_.sync();
    unacknowledged_ = 0;  // the resume's next_seq confirms them
    const std::string stored = std::to_string(result_.points) + " points are in " + file_.path();
    if (!session_.reconnectable() || options_.reconnect_timeout_ms <= 0) {
      throw TransportError(std::string(error.what()) + "; " + stored);
    }
    if (options_.notice) options_.notice(std::string(error.what()) + "; reconnecting");
    const auto started = Clock::now();
    std::string last_error = error.what();
    while (ms_since(started) < options_.reconnect_timeout_ms) {
      try {
        session_.reopen();
        session_.hello(2000, digitizer_Capability_CAP_RESUME);
        complete_last_line();
        request_id_ = send_resume();
        resuming_ = true;
        accepted_ = false;
        ++result_.reconnects;
        if (options_.notice) options_.notice("reconnected; resuming at point " + std::to_string(expected_seq_));
        if (stop_ != Stop::kNone) request_pause();
        return;
      } catch (const TransportError& e) {
        last_error = e.what();
      } catch (const DeviceError& e) {
        last_error = e.what();
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
    }
    throw TransportError(last_error + "; gave up reconnecting after " +
                         std::to_string(options_.reconnect_timeout_ms / 1000) + " s; " + stored +
                         " (continue with scan --resume)");
  }

  // Stores one message; true when the scan is over.
  bool handle(const digitizer_Envelope& message) {
    switch (message.which_body) {
      case digitizer_Envelope_accepted_tag:
        if (message.body.accepted.request_id == request_id_) {
          accepted_ = true;
          if (expected_seq_ == 0) expected_seq_ = message.body.accepted.first_seq;
          file_.accepted();
        }
        if (stop_ == Stop::kAsked && message.body.accepted.request_id == pause_id_) stop_ = Stop::kPaused;
        return false;
      case digitizer_Envelope_fault_tag: {
        const digitizer_Fault& f = message.body.fault;
        if (f.request_id == request_id_ && !accepted_) {
          throw ScanRefused(session_.device_name() + (resuming_ ? ": cannot resume: " : ": scan refused (") +
                            (resuming_ ? "" : std::string(fault_name(f.code)) + "): ") + f.detail +
                            (resuming_ ? "; " + std::to_string(result_.points) + " points are in " + file_.path() : ""));
        }
        // A pause refused because the scan just ended: ScanDone follows.
        if (f.request_id != 0 && f.request_id == pause_id_) return false;
        file_.append(message);
        ++result_.faults;
        result_.last_fault = f.code;
        result_.last_fault_detail = f.detail;
        return false;
      }
      case digitizer_Envelope_points_tag:
        store_points(message);
        return false;
      case digitizer_Envelope_line_done_tag:
        // One before the Accepted belongs to a replay, like the points before it.
        if (accepted_) store_line_done(message);
        return false;
      case digitizer_Envelope_scan_done_tag:
        if (message.body.scan_done.scan_id != scan_id_) return false;
        file_.append(message);
        acknowledge();
        file_.sync();
        result_.done = message.body.scan_done;
        result_.finished = true;
        session_.flush(1000);
        return true;
      default:
        return false;
    }
  }

  // Makes what the file holds durable, then tells the device it may free those points: a point is
  // acknowledged only once it would survive a power loss. Batched (ack_batch_points, ack_batch_ms,
  // and whenever the link falls quiet) so one fdatasync covers many points.
  void acknowledge() {
    if (unacknowledged_ == 0) return;
    file_.sync();
    digitizer_Envelope ack = digitizer_Envelope_init_zero;
    ack.which_body = digitizer_Envelope_point_ack_tag;
    ack.body.point_ack.seq = expected_seq_ - 1;
    session_.send(ack);
    unacknowledged_ = 0;
  }

  void store_points(const digitizer_Envelope& message) {
    // Before the device accepted this scan or resume, points are a replay of the ring from an
    // earlier session (another scan's unacknowledged tail, or ours before ResumeScan took
    // effect); after the Accepted the device sends from where it said.
    if (!accepted_) return;
    const digitizer_PointBatch& batch = message.body.points;
    const uint32_t count = static_cast<uint32_t>(point_batch_size(batch));
    if (count == 0) return;
    if (expected_seq_ == 0) expected_seq_ = batch.first_seq;
    if (!seq_before(expected_seq_, batch.first_seq + count)) return;  // all stored already
    if (seq_before(expected_seq_, batch.first_seq)) {
      throw DeviceError(session_.device_name() + ": points " + std::to_string(expected_seq_) + " to " +
                        std::to_string(batch.first_seq - 1) + " never arrived; the rest is in " + file_.path());
    }
    if (batch.first_seq == expected_seq_) {
      file_.append(message);
    } else {
      // Resent from before what the file has (a replay after a reconnect): store only the new tail.
      PointSample points[kMaxPointsPerBatch];
      size_t expanded = 0;
      if (point_batch_expand(batch, points, &expanded) != Status::kOk) {
        throw DeviceError(session_.device_name() + ": an inconsistent point batch at point " + std::to_string(batch.first_seq));
      }
      const size_t skip = expected_seq_ - batch.first_seq;
      digitizer_Envelope tail = digitizer_Envelope_init_zero;
      tail.which_body = digitizer_Envelope_points_tag;
      point_batch_begin(&tail.body.points, points[skip].seq, points[skip].line);
      for (size_t i = skip; i < expanded; ++i) point_batch_append(&tail.body.points, points[i]);
      file_.append(tail);
    }
    const uint32_t added = batch.first_seq + count - expected_seq_;
    // What the file's last line holds, for a LineDone the device will not send again.
    if (!have_tail_ || batch.line != tail_line_) tail_line_points_ = 0;
    have_tail_ = true;
    tail_line_ = batch.line;
    tail_line_points_ += added;
    tail_line_end_ = batch.flags_count == count && (batch.flags[count - 1] & digitizer_PointFlag_POINT_LINE_END) != 0;
    expected_seq_ = batch.first_seq + count;
    result_.points += added;
    if (unacknowledged_ == 0) first_unacknowledged_ = Clock::now();
    unacknowledged_ += added;
    if (unacknowledged_ >= options_.ack_batch_points || ms_since(first_unacknowledged_) >= options_.ack_batch_ms) {
      acknowledge();
    }
    progress_.points = result_.points;
    if (options_.progress) options_.progress(progress_);
  }

  Session& session_;
  ScanSink& file_;
  const CaptureOptions& options_;
  uint32_t scan_id_;
  CaptureResult result_;
  CaptureProgress progress_;
  uint32_t request_id_ = 0;
  bool resuming_ = false;
  bool accepted_ = false;
  uint32_t expected_seq_ = 0;  // 0: take the first batch's numbering
  uint32_t frames_seen_ = 0;  // whole frames counted when last looked at
  bool have_last_line_ = false;
  uint32_t last_line_ = 0;
  // The line of the last stored point: its number, its points so far, whether that point ends it.
  bool have_tail_ = false;
  uint32_t tail_line_ = 0, tail_line_points_ = 0;
  bool tail_line_end_ = false;
  Stop stop_ = Stop::kNone;
  uint32_t pause_id_ = 0;
  uint32_t unacknowledged_ = 0;  // points stored but not yet durable and acknowledged
  Clock::time_point first_unacknowledged_{};
  Clock::time_point stop_asked_{}, quiet_since_{};
};

}  // namespace

CaptureResult capture_scan(Session& session, const digitizer_Hello& device, digitizer_ScanRequest request,
                           ScanSink& file, const CaptureOptions& options) {
  digitizer_Envelope message = digitizer_Envelope_init_zero;
  message.which_body = digitizer_Envelope_hello_tag;
  message.body.hello = device;
  file.append(message);
  return capture_pass(session, request, file, options);
}

CaptureResult capture_pass(Session& session, const digitizer_ScanRequest& request, ScanSink& file,
                           const CaptureOptions& options) {
  digitizer_Envelope start = digitizer_Envelope_init_zero;
  start.which_body = digitizer_Envelope_scan_request_tag;
  start.body.scan_request = request;
  const uint32_t id = session.send(start);
  file.append(start);
  file.sync();
  Capture capture(session, file, options, request);
  return capture.run(id, false);
}

CaptureResult resume_capture(Session& session, const ScanData& stored, ScanSink& file,
                             const CaptureOptions& options) {
  if (!stored.request) throw ScanRefused(file.path() + ": has no scan request; there is nothing to resume");
  Capture capture(session, file, options, stored.passes.empty() ? *stored.request : stored.passes.back());
  return capture.resume(stored);
}

}  // namespace dg::host
