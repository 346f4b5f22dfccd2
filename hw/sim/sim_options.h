// Options of the simulated device, parsed from "key=value" pairs (the sim: URI's query).
#pragma once
#include <cstdint>
#include <string>

#include "firmware/core/device.h"
#include "hw/sim/sim_board.h"

namespace dg::sim {

// The settings apply_sim_option() takes, for the programs' --help.
extern const char kSimOptionsHelp[];

struct SimOptions {
  SimConfig config{};
  std::string device_id = "SIM-0001";
  // Host silence in virtual seconds (0: never). Virtual time runs some hundred times faster than
  // real time during a scan, so this is about a second of a silent host.
  uint32_t host_silence_s = 300;
  dg::HostSilence on_host_silence = dg::HostSilence::kPause;
  bool require_homing = false;
  int32_t compensate_steps = -1;  // the firmware's backlash compensation; -1: the table's play
  uint32_t watchdog_ms = 0;       // the firmware starts the board's watchdog with this timeout (0: not)
  std::string settings_file;      // the simulated settings flash kept in this file between runs ("": none)
};

// Applies one "key=value" pair: part, seed, noise_um, outliers, outlier_mm, inch,
// gauge_delay_us, clock_low_us and clock_high_us (each bit's clock phases), latch_delay_us and latch_jitter_us (when the gauge takes its reading after REQ),
// plunger_mm_s (the plunger's fastest fall after the part), mute (gauge never answers), drop_edge (a CK pulse missing from
// every frame), id, host_silence_s, on_host_silence (pause, continue, abort), start_x_mm,
// start_y_mm (where the table starts), estop_at_ms, estop_ms (the e-stop pressed then, that long),
// watchdog_ms (the firmware's watchdog timeout; 0: none), hang_at_ms (the main loop hangs then),
// switches (nc, open, stuck; 1 and 0 for nc and open), switch_bounce_us, glitch_ms, x_wire_cut_ms,
// require_homing, settings_file (the settings flash kept in a file between runs), gauge
// (digimatic, caliper), backlash_um (the
// screws' play), compensate_um (the firmware's compensation; default the play), and the machine's
// errors: squareness_urad, scale_x_ppm, scale_y_ppm, straightness_x_um, straightness_y_um, lead_error_um, lead_mm, flatness_um, drift_um_per_h, warmup_um, warmup_min, machine_seed,
// machine=typical|ideal, and the part's placement: part_x_mm, part_y_mm, part_angle_deg. Returns an error
// message, or empty on success.
std::string apply_sim_option(const std::string& pair, SimOptions* options);

}  // namespace dg::sim
