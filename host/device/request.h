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

// Waits up to timeout_ms for the message of type `tag` that answers request `id` (a result that
// follows the request's acceptance, such as a TouchResult); a Fault for it throws DeviceError.
digitizer_Envelope wait_for_answer(Session& session, uint32_t id, pb_size_t tag, int timeout_ms);

}  // namespace dg::host
