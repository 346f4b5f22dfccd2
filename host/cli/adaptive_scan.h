// scan --adaptive: after the coarse pass, rounds of new points where the part bends, each run of
// them a pass of its own in the same scan file, until every point is predicted within the tolerance.
#pragma once
#include <cstddef>
#include <string>

#include "digitizer.pb.h"
#include "host/device/capture.h"
#include "host/device/session.h"
#include "host/scan/adaptive_sampling.h"
#include "host/scan/scan_sink.h"

namespace dg::host {

struct AdaptiveOptions {
  double tolerance_mm = 0;
  double min_step_mm = 0;  // 0: the coarse step / 8
  bool quiet = false;
};

struct AdaptiveResult {
  int rounds = 0;
  size_t passes = 0;         // runs measured, each a pass
  size_t new_points = 0;
  RefinementPlan last;       // the plan that ended it (no runs: done; else the pass that failed)
  bool completed = true;     // false: a pass ended early (a fault, an abort, Ctrl-C)
  bool fit_kept = false;     // the tolerance fit kept the tolerance, validated between the samples
  std::string fit_reason;    // else why not
  CaptureResult failed;      // that pass's result
};

// Reads `path` (which `file` appends to), plans, measures the plan's runs as one-line raster passes
// with the coarse request's reading settings, and again, until the plan is empty; then fits to the
// tolerance with validation, and where that fails, refines around its failures and goes on, until
// the fit keeps the tolerance or nothing is left to split. The coarse
// request must have the same step along x and y. Throws std::invalid_argument for a request it
// cannot refine (fly mode, reference readings, unequal steps).
AdaptiveResult refine_scan(Session& session, ScanSink& file, const std::string& path, const digitizer_ScanRequest& coarse,
                           const AdaptiveOptions& adaptive, const CaptureOptions& options);

// Refused before the table moves: why `request` cannot be the coarse pass of an adaptive scan ("" if it can).
std::string adaptive_refusal(const digitizer_ScanRequest& request);

}  // namespace dg::host
