// Capturing a scan from a device into a scan file, point by point, acknowledging what is stored.
#pragma once
#include <cstdint>
#include <functional>

#include "digitizer.pb.h"
#include "host/device/session.h"
#include "host/scan/scan_file.h"

namespace dg::host {

struct CaptureProgress {
  uint32_t points = 0;
  uint32_t points_total = 0;
  uint32_t lines = 0;
};

struct CaptureResult {
  digitizer_ScanDone done = digitizer_ScanDone_init_zero;
  uint32_t points = 0;
  uint32_t lines = 0;
  uint32_t faults = 0;
  digitizer_FaultCode last_fault = digitizer_FaultCode_FAULT_NONE;
  std::string last_fault_detail;
};

struct CaptureOptions {
  // Heartbeat: after heartbeat_ms without a message the host asks for the device's status; a
  // device that answers nothing for silence_timeout_ms is declared silent.
  int heartbeat_ms = 300;
  int silence_timeout_ms = 1000;
  std::function<void(const CaptureProgress&)> progress;
};

// Writes the device's Hello and the request, starts the scan and stores every
// message the device sends until ScanDone. Throws DeviceError when the device
// refuses the scan or falls silent; everything received so far stays in the file.
CaptureResult capture_scan(Session& session, const digitizer_Hello& device,
                           digitizer_ScanRequest request, ScanFileWriter& file,
                           const CaptureOptions& options);

}  // namespace dg::host
