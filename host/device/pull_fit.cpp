// The pull exchange: one command, one FitResult (points still streaming in are not ours to take).
#include "host/device/pull_fit.h"

#include <chrono>
#include <string>

namespace dg::host {

digitizer_FitResult pull_fit(Session& session, const digitizer_Hello& device, digitizer_DeviceFitModel model,
                             int timeout_ms) {
  if ((device.capabilities & digitizer_Capability_CAP_DEVICE_FIT) == 0) {
    throw DeviceError(std::string("device ") + device.device_id + " does not fit surfaces (no CAP_DEVICE_FIT)");
  }
  digitizer_Envelope request = digitizer_Envelope_init_zero;
  request.which_body = digitizer_Envelope_command_tag;
  request.body.command.kind = digitizer_CommandKind_CMD_PULL_FIT;
  request.body.command.fit_model = model;
  const uint32_t id = session.send(request);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    digitizer_Envelope reply;
    if (left.count() <= 0 || !session.receive(&reply, static_cast<int>(left.count()))) {
      throw DeviceError("the device did not answer the fit request within " + std::to_string(timeout_ms) + " ms");
    }
    if (reply.which_body == digitizer_Envelope_fit_result_tag && reply.id == id) return reply.body.fit_result;
    if (reply.which_body == digitizer_Envelope_fault_tag && reply.body.fault.request_id == id) {
      throw DeviceError(std::string("the device refused the fit request: ") + fault_name(reply.body.fault.code) +
                        " (" + reply.body.fault.detail + ")");
    }
  }
}

}  // namespace dg::host
