// What the scan engine needs of a gauge: start a reading, poll it, its deadline and its value.
#pragma once
#include <cstdint>

#include "common/status.h"

namespace dg {

class Probe {
 public:
  enum class State : uint8_t { kIdle, kReading, kDone, kFailed };

  // Starts a read; kBusy if one is running.
  virtual Status start() = 0;
  // Advances timeouts and finishes the frame. Call from the main loop.
  virtual State poll() = 0;
  // The time by which poll() must run again to notice a timeout.
  virtual uint64_t deadline_us() const = 0;
  // After kDone: the reading in nanometres.
  virtual int64_t value_nm() const = 0;
  // After kFailed: why (kTimeout or kBadEncoding).
  virtual Status error() const = 0;

 protected:
  ~Probe() = default;
};

}  // namespace dg
