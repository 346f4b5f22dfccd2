// `digitizer filter`: the LTS noise filter, with every outlier it finds listed.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

#include "host/scan/lts_filter.h"

namespace dg::host {

struct FilterArgs {
  std::string input, output;
  std::string outliers;  // where the condemned points go; empty: OUTPUT.outliers.csv
  std::string unjudged;  // where the points the filter could not judge go; empty: OUTPUT.unjudged.csv
  bool replace_outliers = false;  // put the estimate in an outlier's place instead of leaving it out
  LtsOptions options;
};

CLI::App* add_filter_command(CLI::App& app, FilterArgs& args);
int run_filter(const FilterArgs& args);

}  // namespace dg::host
