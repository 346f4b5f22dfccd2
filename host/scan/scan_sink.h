// What a scan holds, and where a capture stores it as it arrives: the interface between the link and
// whatever keeps the scan (the scan file implements it), so the device code knows no file format.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/proto/point_batch.h"
#include "digitizer.pb.h"

namespace dg::host {

// Everything a stored scan says, with points expanded.
struct ScanData {
  std::optional<digitizer_Hello> device;
  std::optional<digitizer_ScanRequest> request;  // the first pass's (the whole scan's extent and settings)
  // Every pass's request in order: one for a plain scan; an adaptive scan (scan --adaptive) adds a
  // pass for each run of new points, each begun after the one before it ended. The points of a
  // scan of several passes are read in order of y then x, a line for each y.
  std::vector<digitizer_ScanRequest> passes;
  size_t last_pass_first_point = 0;  // where the last pass's points begin, read in stored order
  std::optional<digitizer_Repeatability> repeatability;  // measured at the first point before the scan
  std::vector<PointSample> points;
  std::vector<digitizer_LineDone> lines;
  std::optional<digitizer_ScanDone> done;  // the last pass's end (none while it runs)
  uint64_t device_time_us = 0;             // every pass's duration, summed
  std::vector<digitizer_Fault> faults;
  std::vector<std::string> warnings;  // e.g. a cut-off last record
  // The table calibration that corrects the points (the last calibration record's JSON); the
  // points above are as the device measured them.
  std::optional<std::string> calibration_json;
  uint64_t records = 0;
  uint64_t complete_bytes = 0;  // length of the whole records (less than the file after a crash)
};

// Receives every message of a scan in the order it arrived. The capture acknowledges points to the
// device only after sync() returns, so a sink must hold what it was given by then; it throws when it
// cannot (the capture stops and the device keeps the unacknowledged points).
class ScanSink {
 public:
  virtual ~ScanSink() = default;
  virtual void append(const digitizer_Envelope& message) = 0;
  virtual void sync() = 0;
  // The device accepted the scan: a sink that keeps a new scan out of sight until then (so a
  // refused scan leaves nothing behind) shows it now.
  virtual void accepted() {}
  // Where the points are, for messages ("part.scan").
  virtual const std::string& path() const = 0;
};

}  // namespace dg::host
