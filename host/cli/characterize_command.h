// `digitizer characterize`: curvature, surface types, regions and a suggested net (Koivunen and Bajcsy 1992, 5.3).
#pragma once
#include <CLI/CLI.hpp>
#include <string>

namespace dg::host {

struct CharacterizeArgs {
  std::string input, output;
  int neighbours = 25;
  bool robust = false;
  double zero_curvature = 0;
  bool quiet = false;
};

CLI::App* add_characterize_command(CLI::App& app, CharacterizeArgs& args);
int run_characterize(const CharacterizeArgs& args);

}  // namespace dg::host
