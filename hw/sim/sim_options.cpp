// Parsing of simulator options with a clear message for each bad value.
#include "hw/sim/sim_options.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace dg::sim {

const char kSimOptionsHelp[] =
    "Simulated device settings (key=value):\n"
    "  part=dome|saddle|canister|flat|ballplate|sphere|stepgauge  seed=N  noise_um=X\n"
    "  outliers=RATE  outlier_mm=X  inch=0|1  gauge_delay_us=N  mute=0|1  drop_edge=BIT  id=NAME\n"
    "  latch_delay_us=N latch_jitter_us=S (the gauge reads N us after REQ, sigma S)\n"
    "  clock_low_us=N clock_high_us=N (each bit's clock phases; 200 and 200 by default)\n"
    "  plunger_mm_s=V (the plunger falls after the part at most V mm/s; 0: at once)\n"
    "  host_silence_s=N (virtual s, 0 never)  on_host_silence=pause|continue|abort\n"
    "  start_x_mm=X start_y_mm=Y (the table's start)  estop_at_ms=T estop_ms=D\n"
    "  watchdog_ms=T (the firmware's watchdog)  hang_at_ms=T (the firmware's main loop hangs then)\n"
    "  switches=nc|open|stuck (normally-closed min switches; open: unwired or cut, stuck: never open)\n"
    "  switch_bounce_us=T (contact chatter at a switch's edge)  glitch_ms=T (a 2 us spike on the\n"
    "  limit and e-stop inputs every T ms)  x_wire_cut_ms=T (the x switch's wire cut at T)\n"
    "  require_homing=0|1  gauge=digimatic|caliper  backlash_um=X  compensate_um=X\n"
    "  settings_file=PATH (the settings flash, where the calibration's summary is kept, in a file)\n"
    "  touch_x_mm=X touch_y_mm=Y (faces the touch probe meets)\n"
    "  the machine's errors (each 0 by default): squareness_urad=X scale_x_ppm=X scale_y_ppm=X\n"
    "  straightness_x_um=X straightness_y_um=Y (the ways bow: x wanders this much at mid-travel of y,\n"
    "  and y at mid-travel of x)  lead_error_um=X lead_mm=L (each screw's periodic error, once a turn)\n"
    "  flatness_um=X (the travel's height error at its largest) drift_um_per_h=X machine_seed=N\n"
    "  warmup_um=X warmup_min=T (the stand settles: Z grows by X (1 - exp(-t / T)))\n"
    "  gauge_tilt_x_urad=X gauge_tilt_y_urad=Y (the gauge's axis leans towards +x, +y)\n"
    "  gauge_scale_ppm=X (the gauge reads its travel this much long)\n"
    "  machine=typical (500 urad, 200 and -150 ppm, straightness 8 and -5 um, screws 3 um a turn of\n"
    "  8 mm, 30 um, gauge tilt 3000 and -2000 urad, gauge scale 400 ppm, no drift)\n"
    "  part_x_mm=X part_y_mm=Y part_angle_deg=A (where the part's own frame lies on the table)\n";
namespace {

bool parse_double(const std::string& text, double* out) {
  if (text.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (errno != 0 || end != text.c_str() + text.size() || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

bool parse_u64(const std::string& text, uint64_t* out) {
  if (text.empty() || text[0] == '-') return false;
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
  if (errno != 0 || end != text.c_str() + text.size()) return false;
  *out = v;
  return true;
}

}  // namespace

std::string apply_sim_option(const std::string& pair, SimOptions* options) {
  const size_t eq = pair.find('=');
  if (eq == std::string::npos) return "expected key=value, got '" + pair + "'";
  const std::string key = pair.substr(0, eq);
  const std::string value = pair.substr(eq + 1);
  SimConfig& c = options->config;
  double d = 0;
  uint64_t u = 0;
  if (key == "part") {
    if (!parse_part(value.c_str(), &c.part.kind)) {
      return "unknown part '" + value + "' (dome, saddle, canister, flat, ballplate, sphere, stepgauge)";
    }
  } else if (key == "seed") {
    if (!parse_u64(value, &u)) return "seed must be a whole number, got '" + value + "'";
    c.seed = u;
  } else if (key == "noise_um") {
    if (!parse_double(value, &d) || d < 0) return "noise_um must be >= 0, got '" + value + "'";
    c.gauge.noise_sigma_mm = d * 1e-3;
  } else if (key == "outliers") {
    if (!parse_double(value, &d) || d < 0 || d > 1) {
      return "outliers is a rate in [0, 1], got '" + value + "'";
    }
    c.gauge.outlier_rate = d;
  } else if (key == "outlier_mm") {
    if (!parse_double(value, &d) || d <= 0) return "outlier_mm must be > 0, got '" + value + "'";
    c.gauge.outlier_mm = d;
  } else if (key == "inch") {
    if (value != "0" && value != "1") return "inch is 0 or 1, got '" + value + "'";
    c.gauge.inch = value == "1";
  } else if (key == "gauge_delay_us") {
    if (!parse_u64(value, &u) || u > 1000000) return "gauge_delay_us must be 0..1000000";
    c.gauge.request_to_clock_us = static_cast<uint32_t>(u);
  } else if (key == "clock_low_us" || key == "clock_high_us") {
    if (!parse_u64(value, &u) || u < 10 || u > 100000) return key + " must be 10..100000";
    (key == "clock_low_us" ? c.gauge.clock_low_us : c.gauge.clock_high_us) = static_cast<uint32_t>(u);
  } else if (key == "latch_delay_us" || key == "latch_jitter_us") {
    if (!parse_u64(value, &u) || u > 100000) return key + " must be 0..100000";
    (key == "latch_delay_us" ? c.gauge.latch_delay_us : c.gauge.latch_jitter_us) = static_cast<uint32_t>(u);
  } else if (key == "plunger_mm_s") {
    if (!parse_double(value, &d) || d < 0) return "plunger_mm_s must be >= 0, got '" + value + "'";
    c.plunger_mm_s = d;
  } else if (key == "mute") {
    if (value != "0" && value != "1") return "mute is 0 or 1, got '" + value + "'";
    c.gauge.mute = value == "1";
  } else if (key == "drop_edge") {
    if (!parse_u64(value, &u) || u >= 52) return "drop_edge is a bit index 0..51";
    c.gauge.drop_rising_edge = static_cast<int>(u);
  } else if (key == "host_silence_s") {
    if (!parse_u64(value, &u) || u > 4000) return "host_silence_s must be 0..4000 (virtual seconds)";
    options->host_silence_s = static_cast<uint32_t>(u);
  } else if (key == "on_host_silence") {
    if (value == "pause") options->on_host_silence = dg::HostSilence::kPause;
    else if (value == "continue") options->on_host_silence = dg::HostSilence::kContinue;
    else if (value == "abort") options->on_host_silence = dg::HostSilence::kAbort;
    else return "on_host_silence is pause, continue or abort, got '" + value + "'";
  } else if (key == "start_x_mm" || key == "start_y_mm") {
    if (!parse_double(value, &d) || d < -2 || d > 250) return key + " must be -2..250, got '" + value + "'";
    const int32_t steps = static_cast<int32_t>(std::llround(d * 1e6 / c.nm_per_step));
    (key == "start_x_mm" ? c.start_x_steps : c.start_y_steps) = steps;
  } else if (key == "estop_at_ms" || key == "estop_ms") {
    if (!parse_u64(value, &u) || u > 100000000) return key + " must be 0..100000000";
    (key == "estop_at_ms" ? c.estop_at_ns : c.estop_for_ns) = u * 1000000;
  } else if (key == "hang_at_ms") {
    if (!parse_u64(value, &u) || u > 100000000) return key + " must be 0..100000000";
    c.hang_at_ns = u * 1000000;
  } else if (key == "watchdog_ms") {
    if (!parse_u64(value, &u) || (u != 0 && (u < 10 || u > 30000))) return key + " must be 0 or 10..30000";
    options->watchdog_ms = static_cast<uint32_t>(u);
  } else if (key == "backlash_um" || key == "compensate_um") {
    if (!parse_double(value, &d) || d < 0 || d > 1000) return key + " must be 0..1000, got '" + value + "'";
    const int32_t steps = static_cast<int32_t>(std::llround(d * 1e3 / c.nm_per_step));
    (key == "backlash_um" ? c.backlash_steps : options->compensate_steps) = steps;
  } else if (key == "touch_x_mm" || key == "touch_y_mm") {
    if (!parse_double(value, &d) || d < 0 || d > 250) return key + " must be 0..250, got '" + value + "'";
    const int32_t steps = static_cast<int32_t>(std::llround(d * 1e6 / c.nm_per_step));
    (key == "touch_x_mm" ? c.touch_x_steps : c.touch_y_steps) = steps;
  } else if (key == "gauge") {
    if (value != "digimatic" && value != "caliper") return "gauge is digimatic or caliper, got '" + value + "'";
    c.caliper = value == "caliper";
  } else if (key == "switches") {
    // 1 and 0 as before: wired, or none (an unwired normally-closed input reads open).
    if (value == "nc" || value == "1") c.switches = SwitchWiring::kNormallyClosed;
    else if (value == "open" || value == "0") c.switches = SwitchWiring::kOpen;
    else if (value == "stuck") c.switches = SwitchWiring::kStuckClosed;
    else return "switches is nc, open or stuck, got '" + value + "'";
  } else if (key == "switch_bounce_us" || key == "glitch_ms" || key == "x_wire_cut_ms") {
    if (!parse_double(value, &d) || d < 0 || d > 1e7) return key + " must be 0..1e7, got '" + value + "'";
    const uint64_t ns = static_cast<uint64_t>(std::llround(d * (key == "switch_bounce_us" ? 1e3 : 1e6)));
    (key == "switch_bounce_us" ? c.switch_bounce_ns : key == "glitch_ms" ? c.glitch_period_ns : c.x_wire_cut_at_ns) = ns;
  } else if (key == "squareness_urad" || key == "scale_x_ppm" || key == "scale_y_ppm") {
    if (!parse_double(value, &d) || std::fabs(d) > 20000) return key + " must be -20000..20000, got '" + value + "'";
    (key == "squareness_urad" ? c.machine.squareness_urad : key == "scale_x_ppm" ? c.machine.scale_x_ppm : c.machine.scale_y_ppm) = d;
  } else if (key == "straightness_x_um" || key == "straightness_y_um") {
    if (!parse_double(value, &d) || std::fabs(d) > 1000) return key + " must be -1000..1000, got '" + value + "'";
    (key == "straightness_x_um" ? c.machine.straightness_x_um : c.machine.straightness_y_um) = d;
  } else if (key == "lead_error_um") {
    if (!parse_double(value, &d) || d < 0 || d > 1000) return key + " must be 0..1000, got '" + value + "'";
    c.machine.lead_error_um = d;
  } else if (key == "lead_mm") {
    if (!parse_double(value, &d) || !(d >= 0.5 && d <= 100)) return key + " must be 0.5..100, got '" + value + "'";
    c.machine.lead_mm = d;
  } else if (key == "gauge_scale_ppm") {
    if (!parse_double(value, &d) || std::fabs(d) > 20000) return key + " must be -20000..20000, got '" + value + "'";
    c.machine.gauge_scale_ppm = d;
  } else if (key == "gauge_tilt_x_urad" || key == "gauge_tilt_y_urad") {
    // Beyond 50 mrad (2.9 degrees) a plunger binds: the stand is broken, not out of true.
    if (!parse_double(value, &d) || std::fabs(d) > 50000) return key + " must be -50000..50000, got '" + value + "'";
    (key == "gauge_tilt_x_urad" ? c.machine.gauge_tilt_x_urad : c.machine.gauge_tilt_y_urad) = d;
  } else if (key == "flatness_um" || key == "drift_um_per_h" || key == "warmup_um") {
    if (!parse_double(value, &d) || std::fabs(d) > 1000) return key + " must be -1000..1000, got '" + value + "'";
    (key == "flatness_um" ? c.machine.flatness_um : key == "warmup_um" ? c.machine.warmup_um : c.machine.drift_um_per_h) = d;
  } else if (key == "warmup_min") {
    if (!parse_double(value, &d) || !(d >= 0.1 && d <= 10000)) return key + " must be 0.1..10000, got '" + value + "'";
    c.machine.warmup_min = d;
  } else if (key == "part_x_mm" || key == "part_y_mm" || key == "part_angle_deg") {
    if (!parse_double(value, &d) || std::fabs(d) > 360) return key + " must be -360..360, got '" + value + "'";
    (key == "part_x_mm" ? c.part.x0_mm : key == "part_y_mm" ? c.part.y0_mm : c.part.angle_deg) = d;
  } else if (key == "machine_seed") {
    if (!parse_u64(value, &u)) return "machine_seed must be a whole number, got '" + value + "'";
    c.machine.map_seed = u;
  } else if (key == "machine") {
    if (value != "typical" && value != "ideal") return "machine is typical or ideal, got '" + value + "'";
    const uint64_t map_seed = c.machine.map_seed;
    c.machine = MachineErrors{};
    c.machine.map_seed = map_seed;
    if (value == "typical") {
      c.machine.squareness_urad = 500, c.machine.scale_x_ppm = 200, c.machine.scale_y_ppm = -150;
      c.machine.straightness_x_um = 8, c.machine.straightness_y_um = -5;
      c.machine.lead_error_um = 3, c.machine.lead_mm = 8;
      c.machine.flatness_um = 30;
      c.machine.gauge_tilt_x_urad = 3000, c.machine.gauge_tilt_y_urad = -2000;
      c.machine.gauge_scale_ppm = 400;
    }
  } else if (key == "require_homing") {
    if (value != "0" && value != "1") return "require_homing is 0 or 1, got '" + value + "'";
    options->require_homing = value == "1";
  } else if (key == "settings_file") {
    if (value.empty()) return "settings_file needs a path";
    options->settings_file = value;
  } else if (key == "id") {
    if (value.empty() || value.size() > 23) return "id must be 1 to 23 characters";
    options->device_id = value;
  } else {
    return "unknown simulator option '" + key + "'";
  }
  return "";
}

}  // namespace dg::sim
