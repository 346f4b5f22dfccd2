// The firmware's configuration for the simulated table and gauge: one definition for
// digitizer-sim and for the QEMU board image, which run the same models.
#pragma once
#include "firmware/core/device.h"
#include "hw/sim/sim_board.h"
#include "hw/sim/sim_options.h"

namespace dg::sim {

// Resolution, probe, capabilities and timing to suit `config`; the device's name, board and the
// host-silence policy are the caller's.
DeviceConfig simulated_device(const SimConfig& config);
// The same, with the device options a simulator's command line sets (its name, host silence,
// homing, compensation); the result points into `options`, which must outlive it.
DeviceConfig simulated_device(const SimOptions& options);

}  // namespace dg::sim
