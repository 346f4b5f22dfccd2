// When the next step is due on a board whose timer is a process that may wake late: chained from
// the last due time while lateness is small (it then does not accumulate), started again from now
// when it is not (catching up would burst steps faster than the motors follow).
#pragma once
#include <cstdint>

namespace dg::gadget {

constexpr uint64_t kLateStepNs = 50000;

inline bool step_late(uint64_t due_ns, uint64_t now_ns) { return now_ns > due_ns && now_ns - due_ns > kLateStepNs; }

// `due_ns`: when the tick that just ran was due; `now_ns`: when it ran; `interval_ns`: what the
// step generator asked for next.
inline uint64_t next_step_due(uint64_t due_ns, uint64_t now_ns, uint32_t interval_ns) {
  return (step_late(due_ns, now_ns) ? now_ns : due_ns) + interval_ns;
}

}  // namespace dg::gadget
