// Virtual time runs hundreds of times faster than the host's clock during a scan, which sets the
// link's timers here rather than at the firmware's defaults.
#include "hw/sim/sim_device.h"

namespace dg::sim {

DeviceConfig simulated_device(const SimConfig& config) {
  DeviceConfig device;
  device.motion.nm_per_step = config.nm_per_step;
  device.firmware_version = DIGITIZER_VERSION;
  device.probe = config.caliper ? digitizer_ProbeType_PROBE_CALIPER_24BIT : digitizer_ProbeType_PROBE_DIGIMATIC;
  device.capabilities = (config.caliper ? digitizer_Capability_CAP_CALIPER_24BIT : digitizer_Capability_CAP_DIGIMATIC) |
                        digitizer_Capability_CAP_DEVICE_FIT | digitizer_Capability_CAP_SIMULATED |
                        digitizer_Capability_CAP_RESUME | digitizer_Capability_CAP_HOMING |
                        digitizer_Capability_CAP_TOUCH_PROBE | digitizer_Capability_CAP_CALIBRATION_SUMMARY |
                        digitizer_Capability_CAP_FLY_SCAN;
  device.gauge_resolution_nm = config.caliper ? (config.gauge.inch ? 12700 : 10000) : (config.gauge.inch ? 2540 : 1000);
  // A 50 ms retransmission timer would fire long before any host could answer (and resend frames
  // the host has, costing wire bytes). 5 s of virtual time is about 25 ms of real time during a
  // scan; lost frames are mostly resent sooner, on repeated acknowledgements.
  device.retransmit_us = 5000000;
  // 300 virtual seconds: about a second of a silent host during a scan.
  device.host_silence_us = 300000000;
  // The firmware compensates the play the simulated screws have.
  device.motion.backlash_x_steps = device.motion.backlash_y_steps = static_cast<uint32_t>(config.backlash_steps);
  // The simulated gauge takes its time like a real one; allow for it.
  device.gauge.first_clock_timeout_us = config.gauge.request_to_clock_us + 100000;
  return device;
}

DeviceConfig simulated_device(const SimOptions& options) {
  DeviceConfig device = simulated_device(options.config);
  device.device_id = options.device_id.c_str();
  device.host_silence_us = options.host_silence_s * 1000000u;
  device.on_host_silence = options.on_host_silence;
  device.require_homing = options.require_homing;
  device.watchdog_ms = options.watchdog_ms;
  if (options.compensate_steps >= 0) {
    device.motion.backlash_x_steps = device.motion.backlash_y_steps = static_cast<uint32_t>(options.compensate_steps);
  }
  return device;
}

}  // namespace dg::sim
