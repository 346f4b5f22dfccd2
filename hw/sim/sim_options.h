// Options of the simulated device, parsed from "key=value" pairs (the sim: URI's query).
#pragma once
#include <cstdint>
#include <string>

#include "hw/sim/sim_board.h"

namespace dg::sim {

struct SimOptions {
  SimConfig config{};
  std::string device_id = "SIM-0001";
};

// Applies one "key=value" pair: part, seed, noise_um, outliers, outlier_mm, inch,
// gauge_delay_us, mute (gauge never answers), drop_edge (a CK pulse missing from
// every frame), id. Returns an error message, or empty on success.
std::string apply_sim_option(const std::string& pair, SimOptions* options);

}  // namespace dg::sim
