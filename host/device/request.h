// One request and its answer: the device echoes the request's id in its reply or fault.
#pragma once
#include "digitizer.pb.h"
#include "host/device/session.h"

namespace dg::host {

// Sends `message` and waits up to timeout_ms for the reply carrying its id (Status, Accepted,
// FitResult...). A Fault for it throws DeviceError with the device's reason; silence throws too.
// Other messages that arrive meanwhile (points of a running scan) are not for this caller and
// are passed over.
digitizer_Envelope request(Session& session, digitizer_Envelope& message, int timeout_ms);

}  // namespace dg::host
