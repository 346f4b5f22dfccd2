// `digitizer verify`: the table's length-measurement error on a ball plate (in its plane) or a
// step gauge (along z), against a stated maximum permissible error, in the manner of ISO 10360-2.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

namespace dg::host {

struct VerifyArgs {
  std::string artefact = "ballplate";  // or "stepgauge": heights along z
  std::string device;        // --device; chosen_device() when empty
  std::string certificate;   // the plate's certified ball centres, or the steps' heights
  std::string x, y;          // stepgauge: the area to scan (MIN:MAX, mm): its tops and the plate beside
  std::string at = "0,0,0";  // where the plate lies: its origin X,Y (mm) and its turn (degrees)
  std::string mpe = "3,250"; // E_MPE = A + L/K um: "A,K"
  double shortest_mm = 0;    // lengths shorter than this are not tested
  double ball_step_mm = 1.0;
  std::string calibration;   // the calibration the scan is corrected by (none: the machine as it is)
  std::string from;          // a stored scan of the plate instead of scanning
  std::string scan_output;   // where the plate's scan is kept (default OUTPUT.scan)
  std::string output;        // the lengths, CSV
  std::string svg;           // a picture of the errors against length
  bool force = false;
  bool quiet = false;
};

constexpr int kExitVerifyFailed = 6;

CLI::App* add_verify_command(CLI::App& app, VerifyArgs& args);
// 0 when every length is within E_MPE, kExitVerifyFailed when one is not.
int run_verify(const VerifyArgs& args);

}  // namespace dg::host
