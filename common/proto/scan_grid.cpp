// Grid size of a scan request: (max - min) / step + 1 nodes per axis, in 64 bits.
#include "common/proto/scan_grid.h"

namespace dg {
namespace {

uint64_t nodes(const digitizer_Range& range, uint32_t step_nm) {
  const int64_t span = static_cast<int64_t>(range.max_nm) - range.min_nm;
  return static_cast<uint64_t>(span) / step_nm + 1;
}

}  // namespace

bool scan_grid(const digitizer_ScanRequest& request, ScanGrid* grid) {
  if (!request.has_x || !request.has_y || request.step_x_nm == 0 || request.step_y_nm == 0 ||
      request.x.max_nm < request.x.min_nm || request.y.max_nm < request.y.min_nm) {
    return false;
  }
  grid->points_per_line = nodes(request.x, request.step_x_nm);
  grid->lines = nodes(request.y, request.step_y_nm);
  const uint64_t every = request.reference_every_lines;
  grid->references = every > 0 ? (grid->lines + every - 1) / every : 0;
  return true;
}

}  // namespace dg
