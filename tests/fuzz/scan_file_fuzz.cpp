// Fuzzes the scan-file reader: damaged files give ScanFileError, never a crash.
#include "host/scan/scan_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    dg::host::parse_scan_bytes(data, size, "fuzz.scan");
  } catch (const dg::host::ScanFileError&) {
  }
  return 0;
}
