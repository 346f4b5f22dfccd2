// The slide: the change due at `due` is made at `now`, so every later change moves by now - due.
#include "hw/hil/real_time_gauge.h"

namespace dg::hil {

bool RealTimeGauge::advance(uint64_t now_ns) {
  const uint64_t due = due_ns();
  if (due == UINT64_MAX || due > now_ns) return false;
  epoch_ns_ += now_ns - due;
  model_.advance();
  return true;
}

}  // namespace dg::hil
