// digitizer: the command-line front end; each subcommand lives in its own *_command file.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstring>
#include <new>
#include <stdexcept>

#include "host/cli/calibrate_command.h"
#include "host/cli/characterize_command.h"
#include "host/cli/config_command.h"
#include "host/cli/config_file.h"
#include "host/cli/curve_command.h"
#include "host/cli/device_choice.h"
#include "host/cli/device_commands.h"
#include "host/cli/doctor_command.h"
#include "host/cli/export_command.h"
#include "host/cli/filter_command.h"
#include "host/cli/fit_command.h"
#include "host/cli/flash_command.h"
#include "host/cli/info_command.h"
#include "host/cli/inspect_command.h"
#include "host/cli/scan_command.h"
#include "host/cli/segment_command.h"
#include "host/cli/self_description.h"
#include "host/cli/superquadric_command.h"
#include "host/cli/verify_command.h"
#include "host/io/standard_output.h"
#include "host/parallel/memory_reuse.h"

namespace {

using namespace dg::host;

// Exit codes (docs/cli.md).
constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;  // device, transport or file error
constexpr int kExitUsage = 2;

}  // namespace

int main(int argc, char** argv) {
  // Huge pages, freed blocks kept, one heap for all threads but in the filter (memory_reuse.h).
  const bool filter_command = argc > 1 && std::strcmp(argv[1], "filter") == 0;
  tune_memory(argv, Restart::kForLargeInput, filter_command ? Heaps::kPerThread : Heaps::kShared);
  // Named here, so that usage lines say "digitizer" and not the path it was started by.
  CLI::App app{"bench digitizer: scan parts on an XY table with a dial gauge", "digitizer"};
  app.require_subcommand(1);
  app.set_version_flag("--version", version_text());

  ScanArgs scan;
  CLI::App* scan_cmd = add_scan_command(app, scan);
  PullArgs pull;
  CLI::App* pull_cmd = add_pull_command(app, pull);
  CurveArgs curve;
  CLI::App* curve_cmd = add_curve_command(app, curve);
  CharacterizeArgs characterize_args;
  CLI::App* characterize_cmd = add_characterize_command(app, characterize_args);
  SuperquadricArgs superquadric;
  CLI::App* superquadric_cmd = add_superquadric_command(app, superquadric);

  ExportArgs export_args;
  CLI::App* export_cmd = add_export_command(app, export_args);
  SegmentArgs segment_args;
  CLI::App* segment_cmd = add_segment_command(app, segment_args);
  CalibrateArgs calibrate_args;
  CLI::App* calibrate_cmd = add_calibrate_command(app, calibrate_args);
  RecorrectArgs recorrect_args;
  CLI::App* recorrect_cmd = add_recorrect_command(app, recorrect_args);
  VerifyArgs verify_args;
  CLI::App* verify_cmd = add_verify_command(app, verify_args);
  InfoArgs info_args;
  CLI::App* info_cmd = add_info_command(app, info_args);
  FilterArgs filter;
  CLI::App* filter_cmd = add_filter_command(app, filter);

  FitArgs fit;
  CLI::App* fit_cmd = add_fit_command(app, fit);
  InspectArgs inspect_args;
  CLI::App* inspect_cmd = add_inspect_command(app, inspect_args);
  DeviceArgs device_args;
  add_device_commands(app, device_args);
  SelfDescriptionArgs self_description;
  add_self_description_commands(app, self_description);
  add_config_command(app);
  DoctorArgs doctor_args;
  add_doctor_command(app, doctor_args);
  FlashArgs flash_args;
  add_flash_command(app, flash_args);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  }
  try {
    // The config file fills the options the command line left out; the build's own man pages and
    // completion, `config show` and `doctor` describe the defaults (and a broken file) instead.
    if (!app.got_subcommand("manpages") && !app.got_subcommand("completion") && !app.got_subcommand("config") &&
        !app.got_subcommand("doctor")) {
      apply_config(app, config_path());
    }
    // Device commands name their device (--device, DIGITIZER_DEVICE or the config file): none
    // falls back to the simulator.
    for (const char* name : {"status", "home", "unlock", "abort", "jog", "repeatability", "touch"}) {
      if (app.got_subcommand(name)) device_args.device = chosen_device(device_args.device);
    }
    // An output named "-" (or "-.EXT") is standard output, as write_file_atomically writes it: at
    // most one per command, and then what the command says moves to standard error so that the
    // data stays clean. A scan file cannot be one.
    if (*scan_cmd && is_standard_output(scan.output)) {
      throw std::invalid_argument("scan -o: a scan file is appended to as points arrive, locked and resumed; give it a file name");
    }
    for (const CLI::App* command : app.get_subcommands()) {
      size_t to_standard_output = 0;
      for (const CLI::Option* option : command->get_options()) {
        const bool output = option->check_lname("output") || option->check_lname("report") ||
                            option->check_lname("deviations") || option->check_lname("outliers");
        for (const std::string& value : option->results()) to_standard_output += output && is_standard_output(value) ? 1 : 0;
      }
      if (to_standard_output > 1) throw std::invalid_argument(command->get_name() + ": only one output can be standard output");
      if (to_standard_output == 1) reserve_standard_output_for_data();
    }
    // "-" alone takes the command's format.
    const struct {
      CLI::App* command;
      std::string* output;
      const char* default_extension;
    } outputs[] = {
        {pull_cmd, &pull.output, ".json"},
        {curve_cmd, &curve.output, ".json"},      {superquadric_cmd, &superquadric.output, ".json"},
        {characterize_cmd, &characterize_args.output, ".csv"}, {segment_cmd, &segment_args.output, ".csv"},
        {fit_cmd, &fit.output, ".json"},          {filter_cmd, &filter.output, ".csv"},
    };
    for (const auto& o : outputs) {
      if (*o.command) *o.output = with_default_format(*o.output, o.default_extension);
    }
    if (*scan_cmd) {
      scan.device = chosen_device(scan.device);
      return run_scan(scan);
    }
    if (*calibrate_cmd) {
      // --from calibrates from a stored scan: no device.
      if (calibrate_args.from.empty()) calibrate_args.device = chosen_device(calibrate_args.device);
      return run_calibrate(calibrate_args);
    }
    if (*recorrect_cmd) return run_recorrect(recorrect_args);
    if (*verify_cmd) {
      if (verify_args.from.empty()) verify_args.device = chosen_device(verify_args.device);
      return run_verify(verify_args);
    }
    if (*export_cmd) return run_export(export_args);
    if (*pull_cmd) {
      pull.device = chosen_device(pull.device);
      return run_pull(pull);
    }
    if (*curve_cmd) return run_curve(curve);
    if (*superquadric_cmd) return run_superquadric(superquadric);
    if (*characterize_cmd) return run_characterize(characterize_args);
    if (*info_cmd) return run_info(info_args);
    if (*segment_cmd) return run_segment(segment_args);
    if (*fit_cmd) return run_fit(fit);
    if (*inspect_cmd) return run_inspect(inspect_args);
    const int flash_result = run_flash_command(app, flash_args);
    if (flash_result >= 0) return flash_result;
    const int doctor_result = run_doctor_command(app, doctor_args);
    if (doctor_result >= 0) return doctor_result;
    const int config_result = run_config_command(app);
    if (config_result >= 0) return config_result;
    const int self_result = run_self_description(app, self_description);
    if (self_result >= 0) return self_result;
    const int device_result = run_device_command(app, device_args);
    if (device_result >= 0) return device_result;
    if (*filter_cmd) return run_filter(filter);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "digitizer: %s\n", e.what());
    return kExitUsage;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "digitizer: out of memory: the input or the fit asked is too large for this machine\n");
    return kExitFailure;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "digitizer: %s\n", e.what());
    return kExitFailure;
  }
  return kExitUsage;
}
