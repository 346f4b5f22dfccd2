// `digitizer superquadric`: the part's volumetric description (Koivunen and Bajcsy 1992, section 5.5) to JSON.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

namespace dg::host {

struct SuperquadricArgs {
  std::string input, output;
  int slices = 10;  // for the rotational check
  std::string revolution;  // SURF.json for the surface of revolution of a rotational part
  bool quiet = false;
};

CLI::App* add_superquadric_command(CLI::App& app, SuperquadricArgs& args);
int run_superquadric(const SuperquadricArgs& args);

}  // namespace dg::host
