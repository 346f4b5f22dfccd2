// Capturing a scan from a device into a sink (the scan file), point by point, acknowledging what is stored;
// after a pulled cable, a restarted host or Ctrl-C, continuing it from the last stored point.
#pragma once
#include <cstdint>
#include <functional>
#include <string>

#include "digitizer.pb.h"
#include "host/device/session.h"
#include "host/scan/scan_sink.h"

namespace dg::host {

// The device refused to start or resume the scan (nothing to resume from this attempt).
class ScanRefused : public DeviceError {
 public:
  using DeviceError::DeviceError;
};

struct CaptureProgress {
  uint32_t points = 0;
  uint32_t points_total = 0;
  uint32_t lines = 0;
};

struct CaptureResult {
  digitizer_ScanDone done = digitizer_ScanDone_init_zero;
  bool finished = false;      // ScanDone arrived
  bool interrupted = false;   // stopped on request; the device's scan is paused and resumable
  uint32_t points = 0;        // in the file, including those stored before a resume
  uint32_t lines = 0;
  uint32_t faults = 0;
  uint32_t reconnects = 0;    // pulled cables survived
  digitizer_FaultCode last_fault = digitizer_FaultCode_FAULT_NONE;
  std::string last_fault_detail;
};

struct CaptureOptions {
  // Heartbeat: after heartbeat_ms without a message the host asks for the device's status; a
  // device from which not one whole frame arrives for silence_timeout_ms is declared silent.
  int heartbeat_ms = 300;
  int silence_timeout_ms = 1000;
  // A device whose frames arrive but bring nothing new for this long (a line that damages nearly
  // every frame) is given up on too, with the damage counted.
  int no_progress_timeout_ms = 30000;
  // When the link breaks (a pulled cable, a device reset) on a transport that can reconnect, try
  // for this long to reach the device again and resume; 0 gives up at once.
  int reconnect_timeout_ms = 30000;
  // Points are acknowledged only after an fdatasync of the file, in batches: once this many are
  // waiting (keep it below the device's ring, Hello.point_ring_capacity), once the oldest has
  // waited this long, and whenever the link falls quiet.
  uint32_t ack_batch_points = 64;
  int ack_batch_ms = 20;
  std::function<void(const CaptureProgress&)> progress;
  // Asked between messages; true stops cleanly (Ctrl-C): the device pauses the scan, what arrives
  // meanwhile is stored, and resume_capture() continues it later.
  std::function<bool()> stop_requested;
  // One-line notices for the user (a reconnect).
  std::function<void(const std::string&)> notice;
};

// Writes the device's Hello and the request, starts the scan and stores every message the device
// sends until ScanDone. Throws DeviceError when the device refuses the scan or falls silent, and
// TransportError when the link is gone for good; everything received so far stays in the file.
CaptureResult capture_scan(Session& session, const digitizer_Hello& device, digitizer_ScanRequest request,
                           ScanSink& file, const CaptureOptions& options);

// A further pass of a scan already in `file` (scan --adaptive): writes its request only, then as
// capture_scan. The file's earlier pass must have ended (a reader refuses a request in the middle).
CaptureResult capture_pass(Session& session, const digitizer_ScanRequest& request, ScanSink& file,
                           const CaptureOptions& options);

// Continues the scan whose file holds `stored` (read from `file`'s path): the device frees the
// points the file has and sends the rest from its ring. Throws DeviceError when the device no
// longer has that scan or those points.
CaptureResult resume_capture(Session& session, const ScanData& stored, ScanSink& file,
                             const CaptureOptions& options);

}  // namespace dg::host
