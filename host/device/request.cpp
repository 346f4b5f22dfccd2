// Waiting for the reply with our id, and turning a fault into a clear error.
#include "host/device/request.h"

#include <chrono>
#include <string>

namespace dg::host {

digitizer_Envelope request(Session& session, digitizer_Envelope& message, int timeout_ms) {
  const uint32_t id = session.send(message);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    digitizer_Envelope reply;
    if (left.count() <= 0 || !session.receive(&reply, static_cast<int>(left.count()))) {
      throw DeviceError(session.device_name() + ": no answer within " + std::to_string(timeout_ms) + " ms");
    }
    if (reply.which_body == digitizer_Envelope_fault_tag && reply.body.fault.request_id == id) {
      throw DeviceError(session.device_name() + ": refused (" + fault_name(reply.body.fault.code) + "): " + reply.body.fault.detail);
    }
    if (reply.id == id && reply.which_body != digitizer_Envelope_fault_tag) return reply;
  }
}

digitizer_Envelope wait_for_answer(Session& session, uint32_t id, pb_size_t tag, int timeout_ms) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  digitizer_Envelope reply;
  while (std::chrono::steady_clock::now() < give_up) {
    if (!session.receive(&reply, 500) || reply.id != id) continue;
    if (reply.which_body == digitizer_Envelope_fault_tag) throw DeviceError(session.device_name() + ": " + reply.body.fault.detail);
    if (reply.which_body == tag) return reply;
  }
  throw DeviceError(session.device_name() + ": no answer within " + std::to_string(timeout_ms / 1000) + " s");
}

}  // namespace dg::host
