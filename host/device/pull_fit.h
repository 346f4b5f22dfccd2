// Fetching the surface the device fitted while it scanned (CMD_PULL_FIT -> FitResult).
#pragma once
#include "digitizer.pb.h"
#include "host/device/session.h"

namespace dg::host {

// Asks for `model` and waits up to timeout_ms for the answer. Throws DeviceError when the device
// lacks the capability, refuses, or falls silent. A FitResult whose status is not FIT_OK is
// returned as it is: the caller says what it means.
digitizer_FitResult pull_fit(Session& session, const digitizer_Hello& device, digitizer_DeviceFitModel model,
                             int timeout_ms);

}  // namespace dg::host
