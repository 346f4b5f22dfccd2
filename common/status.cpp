// Human-readable names for Status values, for error messages.
#include "common/status.h"

namespace dg {

const char* status_name(Status status) {
  switch (status) {
    case Status::kOk: return "ok";
    case Status::kNeedMore: return "need more input";
    case Status::kBadCrc: return "CRC mismatch";
    case Status::kBadLength: return "bad length";
    case Status::kBadEncoding: return "bad encoding";
    case Status::kOverflow: return "buffer overflow";
    case Status::kTimeout: return "timeout";
    case Status::kInvalidArgument: return "invalid argument";
    case Status::kBusy: return "busy";
    case Status::kNotReady: return "not ready";
  }
  return "unknown status";
}

}  // namespace dg
