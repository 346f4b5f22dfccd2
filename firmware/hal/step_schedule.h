// When a board's next step is due: chained from the last due time while the tick ran at most
// `late` after it (so small lateness does not accumulate), restarted from when it ran when later
// (catching up would burst steps faster than the motors can follow).
#pragma once

namespace dg::hal {

// T is the board's timer unit, unsigned: the differences are taken modulo its range, so a
// free-running 32-bit hardware counter may wrap between two steps.
template <typename T>
bool step_late(T due, T now, T late) {
  const T behind = now - due;
  return behind > late && behind <= static_cast<T>(static_cast<T>(~T{0}) >> 1);
}

// `due`: when the tick that just ran was due; `now`: when it ran; `interval`: what the step
// generator asked for next.
template <typename T>
T next_step_due(T due, T now, T interval, T late) {
  return static_cast<T>((step_late(due, now, late) ? now : due) + interval);
}

}  // namespace dg::hal
