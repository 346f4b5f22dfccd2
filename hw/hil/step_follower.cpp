// Sorting is stable, so two edges with one timestamp keep the order they were read in.
#include "hw/hil/step_follower.h"

#include <algorithm>

namespace dg::hil {

StepFollower::StepFollower(int64_t x_steps, int64_t y_steps, bool dir_x, bool dir_y)
    : position_{x_steps, y_steps}, dir_{dir_x, dir_y} {}

void StepFollower::apply(std::vector<Edge>& edges) {
  std::stable_sort(edges.begin(), edges.end(),
                   [](const Edge& a, const Edge& b) { return a.timestamp_ns < b.timestamp_ns; });
  for (const Edge& edge : edges) {
    if (edge.axis < 0 || edge.axis > 1) continue;
    if (edge.line == AxisLine::kDir) {
      dir_[edge.axis] = edge.rising;
    } else if (edge.rising) {
      position_[edge.axis] += dir_[edge.axis] ? 1 : -1;
      ++steps_;
    }
  }
  edges.clear();
}

bool StepFollower::dir_after(const std::vector<Edge>& pending, int axis) const {
  bool level = dir_[axis];
  uint64_t latest = 0;
  bool seen = false;
  for (const Edge& edge : pending) {
    if (edge.axis == axis && edge.line == AxisLine::kDir && (!seen || edge.timestamp_ns >= latest)) {
      level = edge.rising;
      latest = edge.timestamp_ns;
      seen = true;
    }
  }
  return level;
}

}  // namespace dg::hil
