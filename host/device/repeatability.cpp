// The moves and readings of a repeatability measurement, as requests over a session.
#include "host/device/repeatability.h"

#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>

#include "host/device/request.h"

namespace dg::host {
namespace {

digitizer_Status status_of(Session& session) {
  digitizer_Envelope message = digitizer_Envelope_init_zero;
  message.which_body = digitizer_Envelope_command_tag;
  message.body.command.kind = digitizer_CommandKind_CMD_STATUS;
  const digitizer_Envelope reply = request(session, message, 5000);
  if (reply.which_body != digitizer_Envelope_status_tag) throw DeviceError(session.device_name() + ": answered status with something else");
  return reply.body.status;
}

}  // namespace

void move_table_to(Session& session, int32_t x_nm, int32_t y_nm, uint32_t step_nm, uint32_t feed_um_s, int timeout_ms) {
  auto there = [&](const digitizer_Status& s) {
    return std::llabs(static_cast<long long>(s.x_nm) - x_nm) <= step_nm && std::llabs(static_cast<long long>(s.y_nm) - y_nm) <= step_nm;
  };
  const digitizer_Status at = status_of(session);
  if (there(at)) return;
  digitizer_Envelope message = digitizer_Envelope_init_zero;
  message.which_body = digitizer_Envelope_command_tag;
  message.body.command.kind = digitizer_CommandKind_CMD_JOG;
  message.body.command.dx_nm = x_nm - at.x_nm;
  message.body.command.dy_nm = y_nm - at.y_nm;
  message.body.command.feed_um_s = feed_um_s;
  request(session, message, 5000);
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    const digitizer_Status s = status_of(session);
    if (s.state == digitizer_DeviceState_STATE_ALARM) {
      throw DeviceError(session.device_name() + ": alarm while moving to the first point (" + fault_name(s.alarm) +
                        (s.alarm_detail[0] ? std::string(": ") + s.alarm_detail : "") + ")");
    }
    if (s.state != digitizer_DeviceState_STATE_JOGGING) {
      if (!there(s)) {
        throw DeviceError(session.device_name() + ": the table stopped at x " + std::to_string(s.x_nm * 1e-6) + " y " +
                          std::to_string(s.y_nm * 1e-6) + " mm, not at the point it was sent to");
      }
      return;
    }
    if (std::chrono::steady_clock::now() > give_up) {
      throw DeviceError(session.device_name() + ": still moving after " + std::to_string(timeout_ms / 1000) + " s");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

digitizer_Repeatability measure_repeatability(Session& session, uint32_t count) {
  digitizer_Envelope message = digitizer_Envelope_init_zero;
  message.which_body = digitizer_Envelope_command_tag;
  message.body.command.kind = digitizer_CommandKind_CMD_REPEATABILITY;
  message.body.command.count = count;
  const uint32_t id = request(session, message, 5000).id;
  // Each reading follows a 2 mm round trip: allow 5 s for each on a slow table.
  const int timeout_ms = static_cast<int>(10000 + 5000 * count);
  return wait_for_answer(session, id, digitizer_Envelope_repeatability_tag, timeout_ms).body.repeatability;
}

}  // namespace dg::host
