// Capture loop: store first, then acknowledge, so the device frees only what is on disk.
#include "host/device/capture.h"

#include <chrono>

#include "common/proto/scan_grid.h"

namespace dg::host {

CaptureResult capture_scan(Session& session, const digitizer_Hello& device,
                           digitizer_ScanRequest request, ScanFileWriter& file,
                           const CaptureOptions& options) {
  digitizer_Envelope message = digitizer_Envelope_init_zero;
  message.which_body = digitizer_Envelope_hello_tag;
  message.body.hello = device;
  file.append(message);

  digitizer_Envelope start = digitizer_Envelope_init_zero;
  start.which_body = digitizer_Envelope_scan_request_tag;
  start.body.scan_request = request;
  const uint32_t id = session.send(start);
  file.append(start);
  file.sync();

  CaptureResult result;
  CaptureProgress progress;
  ScanGrid grid;
  if (scan_grid(request, &grid)) progress.points_total = static_cast<uint32_t>(grid.points());
  bool accepted = false;
  uint32_t expected_seq = 0;  // 0: take the first batch's numbering
  auto last_heard = std::chrono::steady_clock::now();
  for (;;) {
    if (!session.receive(&message, options.heartbeat_ms)) {
      const auto silent = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - last_heard);
      if (silent.count() >= options.silence_timeout_ms) {
        throw DeviceError(session.device_name() + ": device silent for " + std::to_string(silent.count()) + " ms after " +
                          std::to_string(result.points) + " points; they are in " + file.path());
      }
      // A slow scan (long settling, many samples) may have nothing to say: ask for a sign of life.
      digitizer_Envelope probe = digitizer_Envelope_init_zero;
      probe.which_body = digitizer_Envelope_command_tag;
      probe.body.command.kind = digitizer_CommandKind_CMD_STATUS;
      session.send(probe);
      continue;
    }
    last_heard = std::chrono::steady_clock::now();
    switch (message.which_body) {
      case digitizer_Envelope_accepted_tag:
        if (message.body.accepted.request_id == id) accepted = true;
        break;
      case digitizer_Envelope_fault_tag: {
        const digitizer_Fault& f = message.body.fault;
        if (f.request_id == id && !accepted) {
          throw DeviceError(session.device_name() + ": scan refused (" + fault_name(f.code) +
                            "): " + f.detail);
        }
        file.append(message);
        ++result.faults;
        result.last_fault = f.code;
        result.last_fault_detail = f.detail;
        break;
      }
      case digitizer_Envelope_points_tag: {
        const digitizer_PointBatch& batch = message.body.points;
        const uint32_t count = batch.dx_nm_count;
        if (expected_seq == 0) expected_seq = batch.first_seq;
        if (batch.first_seq + count <= expected_seq) break;  // a duplicate: already stored
        if (batch.first_seq != expected_seq) {
          throw DeviceError(session.device_name() + ": points " + std::to_string(expected_seq) +
                            " to " + std::to_string(batch.first_seq - 1) +
                            " never arrived; the rest is in " + file.path());
        }
        file.append(message);
        expected_seq += count;
        result.points += count;
        digitizer_Envelope ack = digitizer_Envelope_init_zero;
        ack.which_body = digitizer_Envelope_point_ack_tag;
        ack.body.point_ack.seq = expected_seq - 1;
        session.send(ack);
        progress.points = result.points;
        if (options.progress) options.progress(progress);
        break;
      }
      case digitizer_Envelope_line_done_tag:
        file.append(message);
        file.sync();
        ++result.lines;
        progress.lines = result.lines;
        break;
      case digitizer_Envelope_scan_done_tag:
        file.append(message);
        file.sync();
        result.done = message.body.scan_done;
        return result;
      default:
        break;
    }
  }
}

}  // namespace dg::host
