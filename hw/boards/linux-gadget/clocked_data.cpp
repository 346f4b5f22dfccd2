// A Linux kernel (gpiolib's v1 line events) stamps an edge's time in its interrupt handler but
// reads the level for its type later, in a thread; edges that come before the thread runs are
// reported once. So a level that does not change between two kept edges means edges were lost.
#include "hw/boards/linux-gadget/clocked_data.h"

namespace dg::gadget {

void ClockedData::add(uint64_t timestamp_ns, bool level) {
  // Later than a CK edge already answered: that answer may have missed this edge.
  if (timestamp_ns < last_clock_ns_) doubtful_ = true;
  if (count_ == kCapacity) {  // far behind: keep the newest, and say the oldest are gone
    head_ = (head_ + 1) % kCapacity;
    --count_;
    doubtful_ = true;
  }
  edges_[(head_ + count_) % kCapacity] = {timestamp_ns, level};
  ++count_;
}

bool ClockedData::queued_level() const { return count_ > 0 ? edges_[(head_ + count_ - 1) % kCapacity].level : level_; }

bool ClockedData::level_at(uint64_t timestamp_ns) {
  while (count_ > 0 && edges_[head_].timestamp_ns <= timestamp_ns) {
    if (edges_[head_].level == level_) doubtful_ = true;
    level_ = edges_[head_].level;
    head_ = (head_ + 1) % kCapacity;
    --count_;
  }
  last_clock_ns_ = timestamp_ns;
  return level_;
}

bool ClockedData::take_doubtful() {
  const bool doubtful = doubtful_;
  doubtful_ = false;
  return doubtful;
}

}  // namespace dg::gadget
