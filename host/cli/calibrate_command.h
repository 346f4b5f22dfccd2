// `digitizer calibrate`: the table's travel error measured on a flat, and `digitizer recorrect`:
// a stored scan corrected by another calibration.
#pragma once
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "host/geometry/trimmed_face.h"

namespace dg::host {

struct CalibrateArgs {
  std::string artefact = "flat";
  std::string device;      // --device; chosen_device() when empty
  std::string x = "0:100", y = "0:100";
  double step_mm = 5.0;
  unsigned samples = 1;
  double flatness_um = 0;  // the flat's certified flatness, peak to valley
  std::string certificate; // ball plate: its certified ball centres (CSV x_mm,y_mm)
  double ball_step_mm = 1.0;  // ball plate and sphere: grid step of its scan
  double diameter_mm = 0;  // sphere: its certified diameter
  std::string sphere_at;   // sphere: where its top stands on the table, "X,Y" in mm
  double lead_mm = 0;      // sphere: the screws' lead, to fit their periodic error as well (0: not)
  std::string from;        // an existing scan of the artefact instead of scanning
  std::string scan_output; // where the artefact's scan is kept (default OUTPUT.flat.scan, OUTPUT.ballplate.scan, OUTPUT.stepgauge.scan, OUTPUT.sphere.scan)
  std::string output;      // the calibration file
  bool force = false;
  bool quiet = false;
};

struct RecorrectArgs {
  std::string scan;
  std::string calibration;
};

// What an artefact's scan is: where, how finely, by which device, corrected by which calibration.
struct ArtefactScan {
  std::string device, x, y;  // x and y as MIN:MAX
  double step_mm = 1;
  unsigned samples = 1;
  std::string calibration = "none";
  std::string output;
  bool force = false, quiet = false;
};

// Says what to place (`what`), waits for Enter at a terminal, then scans; run_scan's exit code.
int scan_artefact(const ArtefactScan& s, const std::string& what);
// The x and y ranges (MIN:MAX, mm) that hold every point with `margin_mm` around, from 0 up.
void ranges_around(const std::vector<Point2>& points, double margin_mm, std::string* x, std::string* y);

CLI::App* add_calibrate_command(CLI::App& app, CalibrateArgs& args);
CLI::App* add_recorrect_command(CLI::App& app, RecorrectArgs& args);
int run_calibrate(const CalibrateArgs& args);
int run_recorrect(const RecorrectArgs& args);

}  // namespace dg::host
