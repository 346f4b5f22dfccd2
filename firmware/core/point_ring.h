// Fixed-capacity ring of measured points kept until the host confirms it stored them.
#pragma once
#include <cstddef>
#include <cstdint>

#include "common/proto/point_batch.h"

namespace dg {

template <size_t Capacity>
class PointRing {
  static_assert(Capacity > 0, "ring needs room");

 public:
  bool full() const { return count_ == Capacity; }
  bool empty() const { return count_ == 0; }
  size_t size() const { return count_; }
  static constexpr size_t capacity() { return Capacity; }

  // Appends; false when full (the caller waits: points are never dropped).
  bool push(const PointSample& point) {
    if (full()) return false;
    items_[(head_ + count_) % Capacity] = point;
    ++count_;
    return true;
  }
  // The i-th oldest point still held.
  const PointSample& at(size_t i) const { return items_[(head_ + i) % Capacity]; }
  // Frees every point with seq <= `seq`.
  void release_through(uint32_t seq) {
    while (count_ > 0 && static_cast<int32_t>(items_[head_].seq - seq) <= 0) {
      head_ = (head_ + 1) % Capacity;
      --count_;
    }
  }
  void clear() { head_ = count_ = 0; }

 private:
  PointSample items_[Capacity] = {};
  size_t head_ = 0;
  size_t count_ = 0;
};

}  // namespace dg
