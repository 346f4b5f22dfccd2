// Hamdan 2010 splits where the step length L_{i+1}/L_i jumps above a threshold taken from
// the first step. Taking the reference from one step breaks when that step is not typical
// (a probe's first move often is not), so the reference here is the median of the
// current line's steps so far, or of the whole stream while the line has fewer than three. Serpentine
// cross feeds that are no longer than a forward step are caught by the turn test instead.
#include "host/scan/segment.h"

#include <algorithm>
#include <cmath>

namespace dg::host {
namespace {

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<long>(mid), values.end());
  return values[mid];
}

}  // namespace

std::vector<uint32_t> segment_lines(const std::vector<Point3>& points, const SegmentOptions& options) {
  std::vector<uint32_t> line(points.size(), 0);
  if (points.size() < 2) return line;
  // Step lengths (eq. 2) and XY directions.
  const size_t steps = points.size() - 1;
  std::vector<double> length(steps), dx(steps), dy(steps);
  for (size_t i = 0; i < steps; ++i) {
    dx[i] = points[i + 1].x - points[i].x;
    dy[i] = points[i + 1].y - points[i].y;
    const double dz = points[i + 1].z - points[i].z;
    length[i] = std::sqrt(dx[i] * dx[i] + dy[i] * dy[i] + dz * dz);
  }
  const double global_step = median(length);
  const double cos_turn = std::cos(options.max_turn_deg * 3.14159265358979323846 / 180.0);

  uint32_t current = 0;
  std::vector<double> line_steps;  // lengths of the current line's steps
  double dir_x = 0, dir_y = 0;      // the line's direction: sum of its unit XY steps
  for (size_t i = 0; i < steps; ++i) {
    // Until a line has three steps its own median can still be the odd first step.
    const double reference = line_steps.size() < 3 ? global_step : median(line_steps);
    bool breaks = reference > 0 && length[i] > options.length_ratio * reference;
    const double xy = std::hypot(dx[i], dy[i]);
    const double dir_norm = std::hypot(dir_x, dir_y);
    if (!breaks && xy > 0 && dir_norm > 0) {
      const double cos_angle = (dx[i] * dir_x + dy[i] * dir_y) / (xy * dir_norm);
      breaks = cos_angle < cos_turn;
    }
    if (breaks) {
      ++current;
      line_steps.clear();
      dir_x = dir_y = 0;
    } else {
      line_steps.push_back(length[i]);
      if (xy > 0) {
        dir_x += dx[i] / xy;
        dir_y += dy[i] / xy;
      }
    }
    line[i + 1] = current;
  }
  return line;
}

}  // namespace dg::host
