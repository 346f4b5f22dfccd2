// Fuzzes the scan-file reader and what every reader does next (each point's uncertainty, the drift
// removal by the reference readings, the scan's facts): damaged files give ScanFileError and
// unusable readings std::invalid_argument, never a crash.
#include <stdexcept>

#include "host/scan/drift_removal.h"
#include "host/scan/scan_facts.h"
#include "host/scan/scan_file.h"
#include "host/scan/scan_uncertainty.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    dg::host::ScanData scan = dg::host::parse_scan_bytes(data, size, "fuzz.scan");
    (void)dg::host::scan_facts(scan);
    dg::host::ScanPointSigmas sigmas = dg::host::scan_point_sigmas(scan);
    (void)dg::host::remove_drift(scan, &sigmas.sigma_mm, "fuzz.scan");
  } catch (const dg::host::ScanFileError&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
