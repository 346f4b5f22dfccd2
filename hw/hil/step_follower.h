// Follows a stepper table from its driver inputs: STEP rising edges counted up or down by the DIR
// level at that instant. Edges from separate lines arrive in separate queues, so they are merged
// by their kernel timestamps before they are applied: a DIR change read late must not turn steps
// that came before it.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dg::hil {

enum class AxisLine : uint8_t { kStep, kDir };

struct Edge {
  uint64_t timestamp_ns;
  int axis;       // 0 = x, 1 = y
  AxisLine line;
  bool rising;    // logical
};

class StepFollower {
 public:
  // `dir_x`, `dir_y`: the DIR levels when following starts (true = towards +).
  StepFollower(int64_t x_steps, int64_t y_steps, bool dir_x, bool dir_y);

  // Applies a batch of edges, in timestamp order whatever order they come in.
  void apply(std::vector<Edge>& edges);

  // DIR of `axis` once `pending` (edges not yet applied) is: what the line should read now if no
  // edge is still on its way from the kernel.
  bool dir_after(const std::vector<Edge>& pending, int axis) const;

  int64_t x_steps() const { return position_[0]; }
  int64_t y_steps() const { return position_[1]; }
  uint64_t steps() const { return steps_; }

 private:
  int64_t position_[2];
  bool dir_[2];
  uint64_t steps_ = 0;
};

}  // namespace dg::hil
