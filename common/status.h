// Status values returned instead of exceptions throughout common/ and firmware/.
#pragma once

namespace dg {

enum class Status {
  kOk = 0,
  kNeedMore,       // not an error: feed more input
  kBadCrc,
  kBadLength,
  kBadEncoding,    // COBS or protobuf bytes that do not decode
  kOverflow,       // output buffer too small
  kTimeout,
  kInvalidArgument,
  kBusy,
  kNotReady,
};

}  // namespace dg
