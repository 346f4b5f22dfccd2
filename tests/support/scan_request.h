// Scan requests for tests: a grid over a rectangle of the table, in nm.
#pragma once
#include <cstdint>

#include "digitizer.pb.h"

namespace dg::test {

inline digitizer_ScanRequest grid_request(uint32_t scan_id, int32_t x_min_nm, int32_t x_max_nm, int32_t y_max_nm,
                                          uint32_t step_nm, digitizer_ScanPattern pattern) {
  digitizer_ScanRequest r = digitizer_ScanRequest_init_zero;
  r.scan_id = scan_id;
  r.has_x = r.has_y = true;
  r.x.min_nm = x_min_nm;
  r.x.max_nm = x_max_nm;
  r.y.max_nm = y_max_nm;
  r.step_x_nm = r.step_y_nm = step_nm;
  r.pattern = pattern;
  r.feed_um_s = 20000;
  r.probe = digitizer_ProbeType_PROBE_DIGIMATIC;
  return r;
}

}  // namespace dg::test
