// The pull exchange: one command, one FitResult (points still streaming in are not ours to take).
#include "host/device/pull_fit.h"

#include <string>

#include "host/device/request.h"

namespace dg::host {

digitizer_FitResult pull_fit(Session& session, const digitizer_Hello& device, digitizer_DeviceFitModel model,
                             int timeout_ms) {
  if ((device.capabilities & digitizer_Capability_CAP_DEVICE_FIT) == 0) {
    throw DeviceError(std::string("device ") + device.device_id + " does not fit surfaces (no CAP_DEVICE_FIT)");
  }
  digitizer_Envelope message = digitizer_Envelope_init_zero;
  message.which_body = digitizer_Envelope_command_tag;
  message.body.command.kind = digitizer_CommandKind_CMD_PULL_FIT;
  message.body.command.fit_model = model;
  const digitizer_Envelope reply = request(session, message, timeout_ms);
  if (reply.which_body != digitizer_Envelope_fit_result_tag) {
    throw DeviceError(session.device_name() + ": answered the fit request with something else");
  }
  return reply.body.fit_result;
}

}  // namespace dg::host
