// The gauge's DATA line as it was at each CK edge, for a board that sees edges late (a Linux
// process): DATA's own edges, timestamped by the kernel, are kept and replayed up to each CK edge's
// timestamp. Where the record cannot be trusted (an edge reported twice the same way, which is how
// the kernel shows two edges it merged; an edge that arrives after a CK edge that needed it), it
// says so, and the board drops a CK edge: the frame then fails and is read again, instead of
// yielding a wrong number.
#pragma once
#include <cstdint>

namespace dg::gadget {

class ClockedData {
 public:
  explicit ClockedData(bool level = false) : level_(level) {}

  // A DATA edge as the kernel queued it: its time and the level it reported.
  void add(uint64_t timestamp_ns, bool level);
  // The level after every kept edge: what the line reads now if no edge is still on its way.
  bool queued_level() const;
  // DATA at a CK edge at `timestamp_ns` (CK edges come in time order).
  bool level_at(uint64_t timestamp_ns);
  // The record is doubtful (for example the caller waited and the line never matched it).
  void mark_doubtful() { doubtful_ = true; }
  // True once after the record was found doubtful.
  bool take_doubtful();

 private:
  static constexpr int kCapacity = 128;
  struct Edge {
    uint64_t timestamp_ns;
    bool level;
  };
  Edge edges_[kCapacity] = {};
  int head_ = 0, count_ = 0;
  bool level_;
  uint64_t last_clock_ns_ = 0;
  bool doubtful_ = false;
};

}  // namespace dg::gadget
