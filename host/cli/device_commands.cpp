// Each device command is one request through a fresh session; faults become clear errors.
#include "host/cli/device_commands.h"

#include <chrono>
#include <cstdio>
#include <thread>
#include <nlohmann/json.hpp>

#include "host/cli/units.h"
#include "host/device/repeatability.h"
#include "host/device/request.h"
#include "host/scan/calibration_summary.h"
#include "host/scan/table_calibration.h"
#include "host/transport/transport.h"
#include "host/transport/usb_transport.h"

namespace dg::host {
namespace {

const char* state_name(digitizer_DeviceState s) {
  switch (s) {
    case digitizer_DeviceState_STATE_IDLE: return "idle";
    case digitizer_DeviceState_STATE_HOMING: return "homing";
    case digitizer_DeviceState_STATE_JOGGING: return "jogging";
    case digitizer_DeviceState_STATE_SCANNING: return "scanning";
    case digitizer_DeviceState_STATE_PAUSED: return "paused";
    case digitizer_DeviceState_STATE_ALARM: return "alarm";
  }
  return "unknown";
}

// Why the device last started, in words.
const char* reset_name(digitizer_ResetCause cause) {
  switch (cause) {
    case digitizer_ResetCause_RESET_POWER_ON: return "power-on";
    case digitizer_ResetCause_RESET_PIN: return "the reset pin (button or debugger)";
    case digitizer_ResetCause_RESET_WATCHDOG: return "the watchdog: the firmware hung, and the scan it ran is gone";
    case digitizer_ResetCause_RESET_SOFTWARE: return "the firmware itself, after a fault";
    case digitizer_ResetCause_RESET_BROWN_OUT: return "a brown-out: the supply sagged";
    case digitizer_ResetCause_RESET_UNKNOWN: break;
  }
  return "";
}

digitizer_Envelope command(Session& session, digitizer_CommandKind kind, const DeviceArgs& a) {
  digitizer_Envelope message = digitizer_Envelope_init_zero;
  message.which_body = digitizer_Envelope_command_tag;
  message.body.command.kind = kind;
  if (kind == digitizer_CommandKind_CMD_JOG) {
    message.body.command.dx_nm = mm_to_nm(a.dx_mm, "--dx");
    message.body.command.dy_nm = mm_to_nm(a.dy_mm, "--dy");
    message.body.command.feed_um_s = static_cast<uint32_t>(a.feed_mm_s * 1000.0);
  }
  return request(session, message, 5000);
}

// What the status says of the table calibration scans use: when and on which device it was
// measured, and whether that is this device (a scan from another is refused). A file that cannot be
// read is reported, not fatal: the device's own status stands.
nlohmann::json calibration_status(const std::string& path, const char* device_id, const digitizer_Status& s) {
  nlohmann::json j = {{"file", path}};
  try {
    std::string text;
    const TableCalibration c = read_calibration_file(path, &text);
    // Whether the file is the calibration the device was last told of (the same bytes).
    if (s.has_calibration) j["device_has_this_file"] = summarize_calibration(c, text).file_crc32 == s.calibration.file_crc32;
    j["created_utc"] = c.created_utc;
    j["device_id"] = c.device_id;
    j["this_device"] = c.device_id.empty() || c.device_id == device_id;
    j["travel_mm"] = {{"x", {c.x0_mm, c.x1_mm()}}, {"y", {c.y0_mm, c.y1_mm()}}};
    if (c.has_axes) j["axes_created_utc"] = c.axes_created_utc;
    if (c.has_gauge_tilt) j["gauge_tilt_created_utc"] = c.gauge_created_utc;
    if (c.has_gauge_scale) j["gauge_scale_created_utc"] = c.scale_created_utc;
  } catch (const CalibrationError& e) {
    j["problem"] = e.what();
  }
  return j;
}

void print_calibration_status(const nlohmann::json& j) {
  const std::string file = j["file"].get<std::string>();
  if (j.contains("problem")) {
    std::printf("calibration: %s\n", j["problem"].get<std::string>().c_str());
    return;
  }
  const std::string created = j["created_utc"].get<std::string>(), measured_on = j["device_id"].get<std::string>();
  std::printf("calibration: %s, travel measured %s%s%s", file.c_str(), created.empty() ? "at an unknown time" : created.c_str(),
              measured_on.empty() ? "" : " on ", measured_on.c_str());
  std::printf(" over x %.3f..%.3f, y %.3f..%.3f mm", j["travel_mm"]["x"][0].get<double>(), j["travel_mm"]["x"][1].get<double>(),
              j["travel_mm"]["y"][0].get<double>(), j["travel_mm"]["y"][1].get<double>());
  if (j.contains("axes_created_utc")) std::printf(", axes %s", j["axes_created_utc"].get<std::string>().c_str());
  if (j.contains("gauge_tilt_created_utc")) std::printf(", gauge tilt %s", j["gauge_tilt_created_utc"].get<std::string>().c_str());
  if (j.contains("gauge_scale_created_utc")) std::printf(", gauge scale %s", j["gauge_scale_created_utc"].get<std::string>().c_str());
  std::printf("%s\n", j["this_device"].get<bool>() ? "" : ": another device's; scans from this one with it are refused");
  if (j.contains("device_has_this_file") && !j["device_has_this_file"].get<bool>()) {
    std::printf("  this file is not the calibration the device was last told of (another, or edited since)\n");
  }
}

// What the device keeps of its last calibration: as JSON, and in words.
nlohmann::json device_calibration_json(const digitizer_Status& s) {
  if (!s.has_calibration) return nullptr;
  char crc[16];
  std::snprintf(crc, sizeof crc, "%08x", static_cast<unsigned>(s.calibration.file_crc32));
  return {{"version", s.calibration.version},
          {"created_utc", unix_to_utc(s.calibration.created_unix_s)},
          {"parts", calibration_parts_text(s.calibration.parts)},
          {"file_crc32", crc},
          {"kept_through_power_off", s.calibration_kept}};
}

void print_device_calibration(const digitizer_Status& s) {
  if (!s.has_calibration) {
    std::printf("calibrated: not that the device knows (digitizer calibrate tells it)\n");
    return;
  }
  std::printf("calibrated: %s (%s; file CRC %08x)%s\n", unix_to_utc(s.calibration.created_unix_s).c_str(),
              calibration_parts_text(s.calibration.parts).c_str(), static_cast<unsigned>(s.calibration.file_crc32),
              s.calibration_kept ? "" : ", held until the device restarts");
}

int run_status(const DeviceArgs& a) {
  auto transport = open_transport(a.device);
  Session session(*transport);
  const digitizer_Hello hello = session.hello(5000);
  const digitizer_Envelope reply = command(session, digitizer_CommandKind_CMD_STATUS, a);
  if (reply.which_body != digitizer_Envelope_status_tag) throw DeviceError(a.device + ": answered status with something else");
  const digitizer_Status& s = reply.body.status;
  if (a.json) {
    nlohmann::json j = {{"device", hello.device_id},     {"board", hello.board},
                        {"firmware", hello.firmware_version}, {"state", state_name(s.state)},
                        {"x_mm", s.x_nm * 1e-6},         {"y_mm", s.y_nm * 1e-6},
                        {"z_mm", s.z_nm * 1e-6},         {"homed", s.homed},
                        {"scan_id", s.scan_id},          {"points_done", s.points_done},
                        {"points_total", s.points_total}, {"ring_used", s.ring_used},
                        {"alarm", fault_name(s.alarm)},   {"alarm_detail", s.alarm_detail}};
    // The stack's high-water mark, where the board measures it (stack painting on a Cortex-M).
    if (s.stack_size_bytes > 0) j["stack"] = {{"used_bytes", s.stack_used_bytes}, {"size_bytes", s.stack_size_bytes}};
    static const char* const kResetKeys[] = {"unknown", "power-on", "pin", "watchdog", "software", "brown-out"};
    if (s.reset_cause >= 0 && s.reset_cause <= digitizer_ResetCause_RESET_BROWN_OUT) j["last_reset"] = kResetKeys[s.reset_cause];
    j["device_calibration"] = device_calibration_json(s);
    if (!a.calibration.empty() && a.calibration != "none") j["calibration"] = calibration_status(a.calibration, hello.device_id, s);
    std::printf("%s\n", j.dump(1).c_str());
    return 0;
  }
  std::printf("device %s (%s, firmware %s): %s\n", hello.device_id, hello.board, hello.firmware_version, state_name(s.state));
  std::printf("table at x %.3f y %.3f mm, gauge %.3f mm, %s\n", s.x_nm * 1e-6, s.y_nm * 1e-6, s.z_nm * 1e-6,
              s.homed ? "homed" : "not homed");
  if (s.points_total > 0) std::printf("scan %u: %u of %u points, %u waiting in the ring\n", s.scan_id, s.points_done, s.points_total, s.ring_used);
  if (s.state == digitizer_DeviceState_STATE_ALARM) {
    std::printf("alarm: %s%s%s (digitizer unlock clears it)\n", fault_name(s.alarm), s.alarm_detail[0] ? ": " : "", s.alarm_detail);
  }
  if (reset_name(s.reset_cause)[0] != '\0') std::printf("last reset: %s\n", reset_name(s.reset_cause));
  if (s.stack_size_bytes > 0) {
    std::printf("stack: at most %u of %u bytes used since reset%s\n", s.stack_used_bytes, s.stack_size_bytes,
                s.stack_used_bytes >= s.stack_size_bytes ? " (all of it: it may have overflowed)" : "");
  }
  print_device_calibration(s);
  if (!a.calibration.empty() && a.calibration != "none") print_calibration_status(calibration_status(a.calibration, hello.device_id, s));
  return 0;
}

// Asks for the device's status every 100 ms until `busy` says it is done; a DeviceError saying
// `still` after `limit`.
digitizer_Status wait_until_settled(Session& session, const DeviceArgs& a, bool (*busy)(const digitizer_Status&),
                                    std::chrono::seconds limit, const std::string& still) {
  const auto give_up = std::chrono::steady_clock::now() + limit;
  for (;;) {
    const digitizer_Envelope reply = command(session, digitizer_CommandKind_CMD_STATUS, a);
    if (!busy(reply.body.status)) return reply.body.status;
    if (std::chrono::steady_clock::now() > give_up) throw DeviceError(a.device + ": " + still);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

int run_simple(const DeviceArgs& a, digitizer_CommandKind kind, const char* done) {
  auto transport = open_transport(a.device);
  Session session(*transport);
  session.hello(5000, kind == digitizer_CommandKind_CMD_HOME ? digitizer_Capability_CAP_HOMING : 0);
  command(session, kind, a);
  if (kind == digitizer_CommandKind_CMD_HOME) {
    // Homing takes a while: wait for it to end and say how.
    const digitizer_Status s = wait_until_settled(
        session, a, [](const digitizer_Status& t) { return t.state == digitizer_DeviceState_STATE_HOMING; },
        std::chrono::minutes(3), "still homing after 3 minutes");
    if (!s.homed) {
      throw DeviceError(a.device + ": homing failed (" + fault_name(s.alarm) + (s.alarm_detail[0] ? std::string(": ") + s.alarm_detail : "") + ")");
    }
    std::printf("%s: homed, table at x %.3f y %.3f mm\n", a.device.c_str(), s.x_nm * 1e-6, s.y_nm * 1e-6);
    return 0;
  }
  if (kind == digitizer_CommandKind_CMD_ABORT) {
    // The device takes the abort at once but stops between points (a reading in progress ends
    // first): say "aborted" only once it is idle, and where the scan's points are.
    const digitizer_Status s = wait_until_settled(
        session, a,
        [](const digitizer_Status& t) {
          return t.state == digitizer_DeviceState_STATE_SCANNING || t.state == digitizer_DeviceState_STATE_PAUSED ||
                 t.state == digitizer_DeviceState_STATE_JOGGING || t.state == digitizer_DeviceState_STATE_HOMING;
        },
        std::chrono::seconds(30), "the abort was accepted but the device is still busy after 30 s");
    std::printf("%s: aborted, the device is idle\n", a.device.c_str());
    if (s.ring_used > 0) {
      std::printf("  %u points of scan %u wait in the device: `digitizer scan --resume -o FILE` with the scan's "
                  "file fetches them\n", s.ring_used, s.scan_id);
    }
    return 0;
  }
  std::printf("%s: %s\n", a.device.c_str(), done);
  return 0;
}

int run_touch(const DeviceArgs& a) {
  auto transport = open_transport(a.device);
  Session session(*transport);
  session.hello(5000, digitizer_Capability_CAP_TOUCH_PROBE);
  digitizer_Envelope message = digitizer_Envelope_init_zero;
  message.which_body = digitizer_Envelope_command_tag;
  message.body.command.kind = digitizer_CommandKind_CMD_TOUCH;
  message.body.command.dx_nm = mm_to_nm(a.dx_mm, "--dx");
  message.body.command.dy_nm = mm_to_nm(a.dy_mm, "--dy");
  message.body.command.feed_um_s = static_cast<uint32_t>(a.feed_mm_s * 1000.0);
  const uint32_t id = request(session, message, 5000).id;
  const digitizer_TouchResult t = wait_for_answer(session, id, digitizer_Envelope_touch_result_tag, 600000).body.touch_result;
  if (!t.touched) {
    std::printf("no touch: the table stopped at x %.4f y %.4f mm\n", t.stop_x_nm * 1e-6, t.stop_y_nm * 1e-6);
    return 1;
  }
  std::printf("touch at x %.4f y %.4f mm (table stopped at x %.4f y %.4f mm)\n", t.x_nm * 1e-6, t.y_nm * 1e-6,
              t.stop_x_nm * 1e-6, t.stop_y_nm * 1e-6);
  return 0;
}

int run_repeatability(const DeviceArgs& a) {
  auto transport = open_transport(a.device);
  Session session(*transport);
  session.hello(5000);
  const digitizer_Repeatability r = measure_repeatability(session, a.count);
  std::printf("%u readings at x %.3f y %.3f mm, each after moving 1 mm away and back:\n", r.count, r.x_nm * 1e-6, r.y_nm * 1e-6);
  std::printf("mean %.4f mm, range %.4f mm (%.4f..%.4f), standard deviation %.4f mm\n", r.mean_nm * 1e-6,
              (r.max_nm - r.min_nm) * 1e-6, r.min_nm * 1e-6, r.max_nm * 1e-6, r.stddev_nm * 1e-6);
  return 0;
}

}  // namespace

void add_device_commands(CLI::App& app, DeviceArgs& a) {
  app.add_subcommand("devices", "list the kinds of device this build reaches");
  auto with_device = [&](CLI::App* cmd) {
    cmd->add_option("--device", a.device, "device URI: usb:, sim:part=dome, unix:PATH, tcp:HOST:PORT (else DIGITIZER_DEVICE or the config file)");
    return cmd;
  };
  CLI::App* status = with_device(app.add_subcommand("status", "the device's state, position and scan"));
  status->add_flag("--json", a.json, "as JSON");
  status->add_option("--calibration", a.calibration,
                     "the table calibration scans are corrected by (the config file's, by default): say when it was "
                     "measured and whether on this device (none: say nothing)");
  with_device(app.add_subcommand("home", "home both axes"));
  with_device(app.add_subcommand("unlock", "clear an alarm"));
  with_device(app.add_subcommand("abort", "stop a scan or a move"));
  CLI::App* touch = with_device(app.add_subcommand("touch", "move by DX, DY mm with the touch-trigger probe until it touches"));
  touch->add_option("--dx", a.dx_mm, "mm along x")->capture_default_str();
  touch->add_option("--dy", a.dy_mm, "mm along y")->capture_default_str();
  touch->add_option("--feed", a.feed_mm_s, "mm/s (default 1)")->check(CLI::Range(0.0, 200.0));
  CLI::App* repeat = with_device(app.add_subcommand("repeatability", "read the current point N times, moving away and back each time"));
  repeat->add_option("-n,--count", a.count, "readings (2..64)")->capture_default_str()->check(CLI::Range(2, 64));
  CLI::App* jog = with_device(app.add_subcommand("jog", "move the table by DX, DY mm"));
  jog->add_option("--dx", a.dx_mm, "mm along x")->capture_default_str();
  jog->add_option("--dy", a.dy_mm, "mm along y")->capture_default_str();
  jog->add_option("--feed", a.feed_mm_s, "mm/s (default: the device's)")->check(CLI::Range(0.0, 200.0));
}

// The USB devices that answer to our IDs, then the other ways to reach a device.
static int list_devices() {
  const UsbSelector ids = parse_usb_uri("usb:");
  try {
    const std::vector<UsbDeviceInfo> found = list_usb_devices(ids);
    if (found.empty()) std::printf("usb:   no device %04x:%04x is connected\n", ids.vendor, ids.product);
    for (const UsbDeviceInfo& d : found) {
      std::printf("usb:%04x:%04x%s%s  bus %u address %u  %s%s\n", d.vendor, d.product, d.serial.empty() ? "" : ",serial=",
                  d.serial.c_str(), d.bus, d.address, d.product_name.c_str(), d.problem.empty() ? "" : ("  " + d.problem).c_str());
    }
  } catch (const TransportError& e) {
    std::printf("usb:   %s\n", e.what());
  }
  std::printf("sim:   the simulated table and gauge (always here), e.g. sim:part=dome,seed=7\n");
  std::printf("unix:  a device behind a unix socket, e.g. unix:/tmp/bench.sock (digitizer-sim --listen)\n");
  std::printf("tcp:   a device behind a TCP port, e.g. tcp:bench.local:5555\n");
  std::printf("fault: any device behind a damaged line, e.g. fault:drop=0.01;sim:part=dome\n");
  return 0;
}

int run_device_command(const CLI::App& app, const DeviceArgs& a) {
  if (app.got_subcommand("devices")) {
    return list_devices();
  }
  if (app.got_subcommand("status")) return run_status(a);
  if (app.got_subcommand("home")) return run_simple(a, digitizer_CommandKind_CMD_HOME, "homed");
  if (app.got_subcommand("unlock")) return run_simple(a, digitizer_CommandKind_CMD_UNLOCK, "unlocked");
  if (app.got_subcommand("abort")) return run_simple(a, digitizer_CommandKind_CMD_ABORT, "aborted");
  if (app.got_subcommand("jog")) return run_simple(a, digitizer_CommandKind_CMD_JOG, "jog accepted");
  if (app.got_subcommand("repeatability")) return run_repeatability(a);
  if (app.got_subcommand("touch")) return run_touch(a);
  return -1;
}

}  // namespace dg::host
