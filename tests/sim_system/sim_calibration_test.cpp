// Calibration in the whole system: the simulated table's travel is 30 um out of flat; the table is
// calibrated on a flat, a part scanned later (another scan seed) is corrected by it, a scan outside
// the calibrated travel is refused before the table moves, and a stored scan is re-corrected.
#include <CppUTest/TestHarness.h>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "host/cli/calibrate_command.h"
#include "host/cli/device_commands.h"
#include "host/cli/scan_command.h"
#include "host/cli/verify_command.h"
#include "host/scan/point_reader.h"
#include "host/scan/scan_file.h"
#include "host/scan/table_calibration.h"
#include "hw/sim/machine_errors.h"
#include "hw/sim/parts.h"
#include "hw/sim/sim_options.h"
#include "tests/support/ball_plate.h"
#include "tests/support/standard_output.h"

using namespace dg::host;

namespace {

std::string temp_path(const std::string& name) {
  return std::string(P_tmpdir) + "/dg_calibration_" + std::to_string(getpid()) + "_" + name;
}

std::string certificate(const std::string& path) { return dg::test::write_ball_plate_certificate(path); }

// The simulated step gauge's certificate (docs/step-gauge-sim.csv), as a file.
std::string step_certificate(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "w");
  std::fprintf(f, "height_mm\n");
  for (int k = 0; k < dg::sim::kSteps; ++k) std::fprintf(f, "%g\n", dg::sim::step_height_mm(k));
  std::fclose(f);
  return path;
}

// The arguments for the simulated reference sphere (its top at (20, 15) mm, scanned at 0.5 mm)
// after `base`'s artefact, with the screws' lead when `lead_mm` > 0.
CalibrateArgs sphere_args(const CalibrateArgs& base, const std::string& machine, int seed, double lead_mm) {
  CalibrateArgs sphere = base;
  sphere.artefact = "sphere";
  sphere.certificate.clear();
  sphere.device = "sim:part=sphere,seed=" + std::to_string(seed) + "," + machine;
  sphere.diameter_mm = 2 * dg::sim::kSphereRadiusMm;
  sphere.sphere_at = "20,15";
  sphere.ball_step_mm = 0.5;
  sphere.lead_mm = lead_mm;
  return sphere;
}

// A typical table calibrated over x, y (MIN:MAX) on the simulated flat, step gauge, reference
// sphere (with the screws' 8 mm lead), ball plate and the sphere again into `cal`.
TableCalibration calibrate_typical(const char* machine, const std::string& cal, const char* x, const char* y, int seed,
                                   const std::string& plate_csv) {
  CalibrateArgs flat;
  flat.device = std::string("sim:part=flat,seed=") + std::to_string(seed) + "," + machine;
  flat.x = x, flat.y = y;
  flat.output = cal;
  flat.force = true;
  flat.quiet = true;
  LONGS_EQUAL(0, run_calibrate(flat));
  CalibrateArgs steps = flat;
  steps.artefact = "stepgauge";
  steps.device = std::string("sim:part=stepgauge,seed=") + std::to_string(seed + 3) + "," + machine;
  steps.certificate = step_certificate(cal + ".steps.csv");
  steps.x = "5.5:40.5", steps.y = "6:24";  // the steps' tops only
  steps.ball_step_mm = 0.5;
  LONGS_EQUAL(0, run_calibrate(steps));
  std::remove(steps.certificate.c_str());
  // The sphere with the screws' lead before the plate: the plate's balls then lie where the
  // screws really put them.
  const CalibrateArgs sphere = sphere_args(flat, machine, seed + 2, 8);
  LONGS_EQUAL(0, run_calibrate(sphere));
  CalibrateArgs plate = flat;
  plate.artefact = "ballplate";
  plate.device = std::string("sim:part=ballplate,seed=") + std::to_string(seed + 1) + "," + machine;
  plate.certificate = certificate(plate_csv);
  LONGS_EQUAL(0, run_calibrate(plate));
  // The sphere again, with the axes in place: its tilt and lead no longer carry their stretch.
  LONGS_EQUAL(0, run_calibrate(sphere));
  return read_calibration_file(cal);
}

void remove_calibration(const std::string& cal) {
  for (const char* scan : {"", ".flat.scan", ".stepgauge.scan", ".ballplate.scan", ".sphere.scan"}) std::remove((cal + scan).c_str());
}

constexpr const char* kMachine = "flatness_um=30,noise_um=0.5";

// The calibrated travel, 0..60 x 0..40 mm at 5 mm.
std::string calibrate(const std::string& output) {
  CalibrateArgs a;
  a.device = std::string("sim:part=flat,seed=11,") + kMachine;
  a.x = "0:60", a.y = "0:40";
  a.output = output;
  a.force = true;
  a.quiet = true;
  LONGS_EQUAL(0, run_calibrate(a));
  return output;
}

ScanArgs dome_scan(const std::string& calibration, const std::string& output) {
  ScanArgs s;
  s.device = std::string("sim:part=dome,seed=12,") + kMachine;
  s.calibration = calibration;
  s.output = output;
  s.force = true;
  s.quiet = true;
  return s;
}

// The worst error of a calibrated dome scan off the true dome, corrected and as measured: each
// point at the (x, y) the calibration moved it to, the raw one where the table was told to go, both
// less the plane one flat cannot tell (the map's plane, rescaled by the gauge's scale when
// calibrated, less the flat's own 5 mm).
std::pair<double, double> dome_errors(const TableCalibration& c, const std::string& part) {
  const PointCloud corrected = read_points(part);
  const ScanData raw = read_scan_file(part);
  double worst = 0, worst_raw = 0;
  for (size_t k = 0; k < corrected.points.size(); ++k) {
    const Point3& p = corrected.points[k];
    const double rx = raw.points[k].x_nm * 1e-6, ry = raw.points[k].y_nm * 1e-6;
    // The flat read its 5 mm with the gauge's scale; corrected heights have it taken out.
    const double plane = (c.plane_mm[0] + c.plane_mm[1] * rx + c.plane_mm[2] * ry) / (1 + c.gauge_scale_ppm * 1e-6) - 5.0;
    worst = std::fmax(worst, std::fabs(p.z - dg::sim::shape_height_mm(dg::sim::PartKind::kDome, p.x, p.y) - plane));
    worst_raw = std::fmax(worst_raw, std::fabs(raw.points[k].z_nm * 1e-6 - dg::sim::shape_height_mm(dg::sim::PartKind::kDome, rx, ry) - plane));
  }
  return {worst, worst_raw};
}

// Scans the dome on `device` into `part`, corrected by `cal` (whose contents are `c`), prints its
// worst error under `label` and checks it: more than `raw_floor_mm` off uncorrected, and within
// 2 um and the noise corrected (0.5 um read to 1 um: 0.58 um a reading, up to 3.5 times that).
void check_dome_after_calibration(const TableCalibration& c, const std::string& cal, const std::string& part,
                                  const std::string& device, const char* label, double raw_floor_mm) {
  ScanArgs s = dome_scan(cal, part);
  s.device = device;
  LONGS_EQUAL(0, run_scan(s));
  const auto [worst, worst_raw] = dome_errors(c, part);
  std::printf("\n  %s, dome after calibration: worst %.2f um (uncorrected %.1f um)", label, worst * 1e3, worst_raw * 1e3);
  CHECK(worst_raw > raw_floor_mm);
  CHECK(worst <= 0.002 + 3.5 * 0.00058);
}

// `cal` calibrated on the simulated flat of `machine` over x, y (MIN:MAX); the arguments, for the
// artefacts that follow.
CalibrateArgs calibrate_flat(const std::string& machine, int seed, const std::string& cal, const char* x, const char* y) {
  CalibrateArgs flat;
  flat.device = "sim:part=flat,seed=" + std::to_string(seed) + "," + machine;
  flat.x = x, flat.y = y;
  flat.output = cal;
  flat.force = flat.quiet = true;
  LONGS_EQUAL(0, run_calibrate(flat));
  return flat;
}

// Over 0..60 x 0..40 mm, where the dome lies.
CalibrateArgs calibrate_small_flat(const std::string& machine, int seed, const std::string& cal) {
  return calibrate_flat(machine, seed, cal, "0:60", "0:40");
}

// Over the whole 0..100 mm travel, and the arguments for the ball plate (seed + 1) that follows,
// its certificate written to `plate_csv`.
CalibrateArgs calibrate_flat_for_plate(const std::string& machine, int seed, const std::string& cal, const std::string& plate_csv) {
  CalibrateArgs plate = calibrate_flat(machine, seed, cal, "0:100", "0:100");
  plate.artefact = "ballplate";
  plate.device = "sim:part=ballplate,seed=" + std::to_string(seed + 1) + "," + machine;
  plate.certificate = certificate(plate_csv);
  return plate;
}

// What `digitizer ARGS...` (a device command) prints on standard output.
std::string device_command_output(std::vector<std::string> words, const std::string& capture) {
  CLI::App app{"test", "digitizer"};
  DeviceArgs a;
  add_device_commands(app, a);
  std::vector<const char*> argv{"digitizer"};
  for (const std::string& w : words) argv.push_back(w.c_str());
  app.parse(static_cast<int>(argv.size()), argv.data());
  int status = -1;
  const std::string text = dg::test::printed_by([&] { return run_device_command(app, a); }, capture, status);
  LONGS_EQUAL(0, status);
  return text;
}

}  // namespace

TEST_GROUP(SimCalibration){};

TEST(SimCalibration, ADomeScannedLaterIsCorrectedToItsTrueShapeWithinTwoMicrometresAndTheNoise) {
  const std::string cal = calibrate(temp_path("table.cal.json")), part = temp_path("dome.scan");
  LONGS_EQUAL(0, run_scan(dome_scan(cal, part)));
  const TableCalibration c = read_calibration_file(cal);
  const PointCloud corrected = read_points(part);
  CHECK(!corrected.calibration.empty());
  // What one flat cannot tell: the plane taken out of the map (less the flat's own 5 mm height).
  auto plane = [&](double x, double y) { return c.plane_mm[0] - 5.0 + c.plane_mm[1] * x + c.plane_mm[2] * y; };
  double worst = 0, worst_raw = 0, ss = 0;
  ScanData raw = read_scan_file(part);
  for (size_t k = 0; k < corrected.points.size(); ++k) {
    const Point3& p = corrected.points[k];
    const double truth = dg::sim::shape_height_mm(dg::sim::PartKind::kDome, p.x, p.y);
    const double error = p.z - truth - plane(p.x, p.y);
    worst = std::fmax(worst, std::fabs(error));
    ss += error * error;
    worst_raw = std::fmax(worst_raw, std::fabs(raw.points[k].z_nm * 1e-6 - truth - plane(p.x, p.y)));
  }
  const double rms = std::sqrt(ss / static_cast<double>(corrected.points.size()));
  // 0.5 um of noise read to 1 um: about 0.58 um a reading, up to 3.5 times that over 1,271 points.
  std::printf("\n  dome after calibration: worst %.2f um, RMS %.2f um (uncorrected worst %.1f um)", worst * 1e3, rms * 1e3,
              worst_raw * 1e3);
  CHECK(worst_raw > 0.008);  // the travel over this area is 11 um out of its plane
  CHECK(worst <= 0.002 + 3.5 * 0.00058);
  CHECK(rms <= 0.0009);
  std::remove(part.c_str());
  std::remove(cal.c_str());
  std::remove((cal + ".flat.scan").c_str());
}

// A typical table: 30 um out of flat, 500 urad out of square, 200 and -150 ppm of scale, ways bowed
// 8 and -5 um, the gauge
// leaning 3 mrad towards +x and 2 towards -y and reading 400 ppm long. The flat gives the map, the
// step gauge the gauge's scale, the ball plate the axes, the sphere the gauge's lean; the dome
// then lies where the calibration moves its points.
TEST(SimCalibration, OnATypicalTableFourArtefactsBringADomeWithinTwoMicrometresAndTheNoise) {
  const char* machine = "machine=typical,noise_um=0.5";
  const std::string cal = temp_path("typical.cal.json"), part = temp_path("typical-dome.scan"), plate_csv = temp_path("plate.csv");
  const TableCalibration c = calibrate_typical(machine, cal, "0:100", "0:100", 31, plate_csv);
  CHECK(c.has_axes);
  DOUBLES_EQUAL(200, c.scale_x_ppm, 4 * c.u_scale_x_ppm);
  DOUBLES_EQUAL(-150, c.scale_y_ppm, 4 * c.u_scale_y_ppm);
  DOUBLES_EQUAL(500, c.squareness_urad, 4 * c.u_squareness_urad);
  CHECK(c.has_gauge_tilt);
  DOUBLES_EQUAL(3000, c.gauge_tilt_x_urad, 4 * c.u_gauge_tilt_x_urad);
  DOUBLES_EQUAL(-2000, c.gauge_tilt_y_urad, 4 * c.u_gauge_tilt_y_urad);
  CHECK(c.u_gauge_tilt_x_urad < 100 && c.u_gauge_tilt_y_urad < 100);
  CHECK(c.has_gauge_scale);
  DOUBLES_EQUAL(400, c.gauge_scale_ppm, 4 * c.u_gauge_scale_ppm);
  CHECK(c.u_gauge_scale_ppm < 60);
  check_dome_after_calibration(c, cal, part, std::string("sim:part=dome,seed=33,") + machine, "typical table", 0.008);
  for (const std::string& f : {part, plate_csv}) std::remove(f.c_str());
  remove_calibration(cal);
}

// A ball plate measured before the screws' error was known read the balls' periodic shifts as
// axes: measuring the lead on the sphere then removes those axes (never kept false), a plate
// measured again under the lead's correction is kept, and so is it when the sphere is measured again.
TEST(SimCalibration, AxesMeasuredBeforeTheScrewsErrorWasKnownAreRemovedAndTheOnesAfterKept) {
  const std::string machine = "lead_error_um=4,scale_x_ppm=200,noise_um=0.5";
  const std::string cal = temp_path("order.cal.json"), plate_csv = temp_path("order-plate.csv");
  const CalibrateArgs plate = calibrate_flat_for_plate(machine, 91, cal, plate_csv);
  const CalibrateArgs sphere = sphere_args(plate, machine, 93, 8);
  LONGS_EQUAL(0, run_calibrate(plate));
  CHECK(read_calibration_file(cal).has_axes);
  CHECK_FALSE(read_calibration_file(cal).axes_with_lead);
  LONGS_EQUAL(0, run_calibrate(sphere));
  CHECK_FALSE(read_calibration_file(cal).has_axes);
  CHECK(read_calibration_file(cal).lead.measured);
  LONGS_EQUAL(0, run_calibrate(plate));
  TableCalibration c = read_calibration_file(cal);
  CHECK(c.has_axes && c.axes_with_lead);
  DOUBLES_EQUAL(200, c.scale_x_ppm, 4 * c.u_scale_x_ppm);
  LONGS_EQUAL(0, run_calibrate(sphere));
  c = read_calibration_file(cal);
  CHECK(c.has_axes && c.lead.measured);
  std::remove(plate_csv.c_str());
  remove_calibration(cal);
}

// The ways alone out of straight: the y way bows 15 um in x at mid-travel and the x way -10 um in
// y. Over the dome (0..40 x 0..30 mm) the table stands up to 13 um beside where it was told to,
// which the dome's flanks turn into height. A flat and the ball plate (three rows, three columns)
// measure the bows; a dome scanned later comes back within 2 um and the noise of its true shape.
TEST(SimCalibration, BentWaysAreMeasuredOnABallPlateAndTakenOutOfADomeScannedLater) {
  const std::string machine = "straightness_x_um=15,straightness_y_um=-10,noise_um=0.5";
  const std::string cal = temp_path("bow.cal.json"), part = temp_path("bow-dome.scan"), plate_csv = temp_path("bow-plate.csv");
  LONGS_EQUAL(0, run_calibrate(calibrate_flat_for_plate(machine, 71, cal, plate_csv)));
  const TableCalibration c = read_calibration_file(cal);
  const Straightness& bow = c.straightness;
  CHECK(bow.measured);
  // The simulator's bow over the plate's span between its outer balls (15..85 mm): S (35 / 50)^2.
  std::printf("\n  straightness x %+.2f (u %.2f, true %+.2f), y %+.2f (u %.2f, true %+.2f) um", bow.x_um, bow.u_x_um,
              15 * 0.49, bow.y_um, bow.u_y_um, -10 * 0.49);
  DOUBLES_EQUAL(15 * 0.49, bow.x_um, 4 * bow.u_x_um + 0.2);
  DOUBLES_EQUAL(-10 * 0.49, bow.y_um, 4 * bow.u_y_um + 0.2);
  DOUBLES_EQUAL(0, c.squareness_urad, 4 * c.u_squareness_urad);
  check_dome_after_calibration(c, cal, part, "sim:part=dome,seed=73," + machine, "bent ways", 0.006);
  for (const std::string& f : {part, plate_csv}) std::remove(f.c_str());
  remove_calibration(cal);
}

// The lead screws alone out of true: each moves the table up to 4 um ahead and behind its command
// once a turn of its 8 mm lead, which the dome's flanks turn into height. A flat and the reference
// sphere scanned at 0.5 mm with the lead given measure it; a dome scanned later comes back within
// 2 um and the noise of its true shape.
TEST(SimCalibration, TheScrewsPeriodicErrorIsMeasuredOnASphereAndTakenOutOfADomeScannedLater) {
  const std::string machine = "lead_error_um=4,lead_mm=8,noise_um=0.5";
  const std::string cal = temp_path("lead.cal.json"), part = temp_path("lead-dome.scan");
  const CalibrateArgs flat = calibrate_small_flat(machine, 81, cal);
  CalibrateArgs coarse = sphere_args(flat, machine, 82, 8);
  coarse.ball_step_mm = 2.5;  // 3.2 readings a turn of the screw
  try {
    run_calibrate(coarse);
    FAIL("a screw's error was fitted from too few readings a turn");
  } catch (const std::invalid_argument& error) {
    STRCMP_CONTAINS("--ball-step 2 or less (it is 2.5)", error.what());
  }
  LONGS_EQUAL(0, run_calibrate(sphere_args(flat, machine, 82, 8)));
  const TableCalibration c = read_calibration_file(cal);
  CHECK(c.lead.measured);
  std::printf("\n  lead screws: %.2f um in x (u %.2f), %.2f um in y (u %.2f), true 4; tilt %.0f and %.0f urad (u %.0f)",
              c.lead.amplitude_x_um(), c.lead.u_x_um, c.lead.amplitude_y_um(), c.lead.u_y_um, c.gauge_tilt_x_urad,
              c.gauge_tilt_y_urad, c.u_gauge_tilt_x_urad);
  DOUBLES_EQUAL(4, c.lead.amplitude_x_um(), 4 * c.lead.u_x_um + 0.2);
  DOUBLES_EQUAL(4, c.lead.amplitude_y_um(), 4 * c.lead.u_y_um + 0.2);
  DOUBLES_EQUAL(0, c.gauge_tilt_x_urad, 4 * c.u_gauge_tilt_x_urad);
  // The correction is the simulator's own error, point for point over a turn and beyond.
  dg::sim::SimOptions o;
  for (const char* pair : {"lead_error_um=4", "lead_mm=8"}) STRCMP_EQUAL("", dg::sim::apply_sim_option(pair, &o).c_str());
  for (double t = 0; t <= 40; t += 0.7) {
    double x = 0, y = 0;
    dg::sim::actual_table_xy(o.config.machine, t, t, &x, &y);
    DOUBLES_EQUAL(x - t, c.lead.dx_mm(t), 0.0004);
    DOUBLES_EQUAL(y - t, c.lead.dy_mm(t), 0.0004);
  }
  check_dome_after_calibration(c, cal, part, "sim:part=dome,seed=83," + machine, "lead screws", 0.005);
  std::remove(part.c_str());
  remove_calibration(cal);
}

// The gauge alone out of true, leaning 8 mrad towards +x and 5 towards +y: on the dome's flanks a
// reading lands up to 80 um to the side of where the table stood. A flat (the gauge zero's
// height) and the reference sphere measure the lean; a dome scanned later comes back within
// 2 um and the noise of its true shape.
TEST(SimCalibration, ALeaningGaugeIsMeasuredOnASphereAndTakenOutOfADomeScannedLater) {
  const std::string machine = "gauge_tilt_x_urad=8000,gauge_tilt_y_urad=5000,noise_um=0.5";
  const std::string cal = temp_path("tilt.cal.json"), part = temp_path("tilt-dome.scan");
  const CalibrateArgs flat = calibrate_small_flat(machine, 51, cal);
  CalibrateArgs sphere = flat;
  sphere.artefact = "sphere";
  sphere.device = "sim:part=sphere,seed=52," + machine;
  sphere.diameter_mm = 2 * dg::sim::kSphereRadiusMm;
  sphere.sphere_at = "20.5,14";  // where the user thinks it is, not where it is
  sphere.ball_step_mm = 0.5;
  LONGS_EQUAL(0, run_calibrate(sphere));
  const TableCalibration c = read_calibration_file(cal);
  std::printf("\n  gauge tilt x %.0f (u %.0f, true 8000), y %.0f (u %.0f, true 5000) urad", c.gauge_tilt_x_urad,
              c.u_gauge_tilt_x_urad, c.gauge_tilt_y_urad, c.u_gauge_tilt_y_urad);
  DOUBLES_EQUAL(8000, c.gauge_tilt_x_urad, 4 * c.u_gauge_tilt_x_urad);
  DOUBLES_EQUAL(5000, c.gauge_tilt_y_urad, 4 * c.u_gauge_tilt_y_urad);
  check_dome_after_calibration(c, cal, part, "sim:part=dome,seed=53," + machine, "leaning gauge", 0.02);
  const std::string status = device_command_output({"status", "--device", "sim:part=dome", "--calibration", cal}, temp_path("tilt-status.txt"));
  STRCMP_CONTAINS((", gauge tilt " + c.gauge_created_utc).c_str(), status.c_str());
  std::remove(part.c_str());
  remove_calibration(cal);
}

// The gauge alone out of scale, reading 800 ppm short: the dome's 10 mm read 8 um low at its top.
// A flat and the step gauge (its tops against the plate beside them) measure the scale; a dome
// scanned later comes back within 2 um and the noise of its true shape.
TEST(SimCalibration, AGaugeReadingShortIsMeasuredOnAStepGaugeAndTakenOutOfADomeScannedLater) {
  const std::string machine = "gauge_scale_ppm=-800,noise_um=0.5";
  const std::string cal = temp_path("scale.cal.json"), part = temp_path("scale-dome.scan");
  const CalibrateArgs flat = calibrate_small_flat(machine, 61, cal);
  CalibrateArgs steps = flat;
  steps.artefact = "stepgauge";
  steps.device = "sim:part=stepgauge,seed=62," + machine;
  steps.certificate = step_certificate(cal + ".steps.csv");
  steps.x = "5.5:40.5", steps.y = "6:24";
  steps.ball_step_mm = 0.5;
  LONGS_EQUAL(0, run_calibrate(steps));
  const TableCalibration c = read_calibration_file(cal);
  std::printf("\n  gauge scale %.0f ppm (u %.0f, true -800)", c.gauge_scale_ppm, c.u_gauge_scale_ppm);
  DOUBLES_EQUAL(-800, c.gauge_scale_ppm, 4 * c.u_gauge_scale_ppm);
  check_dome_after_calibration(c, cal, part, "sim:part=dome,seed=63," + machine, "gauge reading short", 0.005);
  for (const std::string& f : {part, steps.certificate}) std::remove(f.c_str());
  remove_calibration(cal);
}

// A sphere of another diameter than the certificate's is refused with both diameters, and the
// calibration file keeps what it had.
TEST(SimCalibration, ASphereOfAnotherDiameterThanItsCertificateIsRefused) {
  const std::string cal = calibrate(temp_path("wrong-sphere.cal.json"));
  CalibrateArgs sphere;
  sphere.artefact = "sphere";
  sphere.device = std::string("sim:part=sphere,seed=54,") + kMachine;
  sphere.diameter_mm = 20;
  sphere.sphere_at = "20,15";
  sphere.output = cal;
  sphere.force = sphere.quiet = true;
  try {
    run_calibrate(sphere);
    FAIL("a sphere of 25.4 mm was taken for one of 20 mm");
  } catch (const CalibrationError& error) {
    STRCMP_CONTAINS("the readings give a sphere 25.", error.what());
    STRCMP_CONTAINS("the certificate says 20.000 mm", error.what());
  }
  CHECK(!read_calibration_file(cal).has_gauge_tilt);
  remove_calibration(cal);
}

// ISO 10360-2 asks for lengths in several positions and orientations: the plate is laid square,
// turned 30 degrees and turned -60 degrees on the typical table, calibrated over 150 x 150 mm, and
// the step gauge turned a quarter for heights. Calibrated, every ball-to-ball
// length is within E_MPE = 3 + L/250 um; the same table uncalibrated fails (its 200 ppm of scale
// alone is 20 um over 100 mm).
TEST(SimCalibration, AVerifiedTypicalTablePassesInThreePlacementsAndFailsUncalibrated) {
  const char* machine = "machine=typical,noise_um=0.5";
  const std::string cal = temp_path("verified.cal.json"), plate_csv = temp_path("verify-plate.csv");
  calibrate_typical(machine, cal, "0:150", "0:150", 41, plate_csv);  // the turned placements reach beyond 100 mm
  const struct {
    const char* at;
    const char* placement;
  } placements[] = {{"0,0,0", ""}, {"40,0,30", ",part_x_mm=40,part_y_mm=0,part_angle_deg=30"},
                    {"20,105,-60", ",part_x_mm=20,part_y_mm=105,part_angle_deg=-60"}};
  for (const auto& p : placements) {
    for (const char* calibration : {"calibrated", "none"}) {
      VerifyArgs v;
      v.device = std::string("sim:part=ballplate,seed=43,") + machine + p.placement;
      v.certificate = plate_csv;
      v.at = p.at;
      v.calibration = std::string(calibration) == "none" ? "none" : cal;
      v.output = temp_path("lengths.csv");
      v.force = true;
      v.quiet = true;
      const int result = run_verify(v);
      std::printf("\n  plate at %s, %s: %s", p.at, calibration, result == 0 ? "pass" : "fail");
      LONGS_EQUAL(std::string(calibration) == "none" ? kExitVerifyFailed : 0, result);
      std::remove(v.output.c_str());
      std::remove((v.output + ".scan").c_str());
    }
  }
  // Along z: the step gauge turned a quarter (its steps along y) at x 36..54 mm, against E_MPE on
  // every height between two steps. Uncalibrated, the gauge's 400 ppm is 4 um over 10 mm.
  const std::string steps_csv = step_certificate(temp_path("verify-steps.csv"));
  for (const char* calibration : {"calibrated", "none"}) {
    VerifyArgs v;
    v.artefact = "stepgauge";
    v.device = std::string("sim:part=stepgauge,seed=44,part_x_mm=60,part_angle_deg=90,") + machine;
    v.certificate = steps_csv;
    v.x = "36:54", v.y = "5.5:40.5";
    v.ball_step_mm = 0.5;
    v.calibration = std::string(calibration) == "none" ? "none" : cal;
    v.output = temp_path("heights.csv");
    v.force = v.quiet = true;
    const int result = run_verify(v);
    std::printf("\n  step gauge turned 90 degrees, %s: %s", calibration, result == 0 ? "pass" : "fail");
    LONGS_EQUAL(std::string(calibration) == "none" ? kExitVerifyFailed : 0, result);
    std::remove(v.output.c_str());
    std::remove((v.output + ".scan").c_str());
  }
  std::remove(steps_csv.c_str());
  std::remove(plate_csv.c_str());
  remove_calibration(cal);
}

TEST(SimCalibration, AScanBeyondTheCalibratedTravelIsRefusedBeforeTheTableMoves) {
  const std::string cal = calibrate(temp_path("small.cal.json")), part = temp_path("wide.scan");
  ScanArgs s = dome_scan(cal, part);
  s.x = "0:70";
  try {
    run_scan(s);
    FAIL("a scan the calibration does not cover was started");
  } catch (const CalibrationError& error) {
    STRCMP_CONTAINS("covers x 0.000..60.000, y 0.000..40.000 mm; the scan asks x 0.000..70.000", error.what());
  }
  CHECK(access(part.c_str(), F_OK) != 0);
  std::remove(cal.c_str());
  std::remove((cal + ".flat.scan").c_str());
}

// A calibration says which device it was measured on. A scan from another device is refused once
// the device has answered, before the table moves and before a file appears; re-correcting a
// stored scan from another device is refused too, and the scan keeps its points as they were.
TEST(SimCalibration, AnotherDevicesCalibrationIsRefusedForAScanAndARecorrection) {
  const std::string cal = calibrate(temp_path("own.cal.json")), part = temp_path("other.scan");
  CHECK(read_calibration_file(cal).device_id == "SIM-0001");
  ScanArgs s = dome_scan(cal, part);
  s.device += ",id=SIM-0002";
  try {
    run_scan(s);
    FAIL("a scan from another device was corrected by this one's calibration");
  } catch (const CalibrationError& error) {
    STRCMP_CONTAINS("measured on device SIM-0001, and these points come from device SIM-0002", error.what());
  }
  CHECK(access(part.c_str(), F_OK) != 0);
  s.calibration = "none";
  LONGS_EQUAL(0, run_scan(s));
  const size_t points = read_scan_file(part).points.size();
  RecorrectArgs r;
  r.scan = part;
  r.calibration = cal;
  CHECK_THROWS(CalibrationError, run_recorrect(r));
  CHECK(!read_scan_file(part).calibration_json);
  LONGS_EQUAL(points, read_scan_file(part).points.size());
  for (const std::string& f : {part, cal, cal + ".flat.scan"}) std::remove(f.c_str());
}


// `status` says when the calibration scans use was measured and on which device, and flags one
// measured on another device.
TEST(SimCalibration, StatusSaysWhenAndOnWhichDeviceTheCalibrationWasMeasured) {
  const std::string cal = calibrate(temp_path("status.cal.json")), out = temp_path("status.txt");
  const TableCalibration c = read_calibration_file(cal);
  const std::string own = device_command_output({"status", "--device", "sim:part=dome", "--calibration", cal}, out);
  STRCMP_CONTAINS(("calibration: " + cal + ", travel measured " + c.created_utc + " on SIM-0001 over x 0.000..60.000, "
                   "y 0.000..40.000 mm\n").c_str(), own.c_str());
  const std::string other = device_command_output({"status", "--device", "sim:part=dome,id=SIM-0002", "--calibration", cal}, out);
  STRCMP_CONTAINS("another device's; scans from this one with it are refused", other.c_str());
  const std::string json = device_command_output({"status", "--device", "sim:part=dome", "--calibration", cal, "--json"}, out);
  STRCMP_CONTAINS("\"this_device\": true", json.c_str());
  for (const std::string& f : {cal, cal + ".flat.scan"}) std::remove(f.c_str());
}

// calibrate tells the device what it measured and when; a simulated board whose settings flash is
// a file keeps that through a restart, so status on a later host (another simulator process) says
// it, and whether a given file is that calibration. A board that stores nothing says so.
TEST(SimCalibration, TheDeviceKeepsWhenAndWhatWasCalibratedForStatusOnAnyHost) {
  const std::string cal = temp_path("kept.cal.json"), out = temp_path("kept.txt"), flash = temp_path("flash.bin");
  std::remove(flash.c_str());
  const std::string device = "sim:part=flat,settings_file=" + flash;
  CalibrateArgs flat;
  flat.device = device + ",flatness_um=30";
  flat.x = "0:60", flat.y = "0:40";
  flat.output = cal;
  flat.force = flat.quiet = true;
  LONGS_EQUAL(0, run_calibrate(flat));
  const TableCalibration c = read_calibration_file(cal);
  const std::string status = device_command_output({"status", "--device", device, "--calibration", cal}, out);
  STRCMP_CONTAINS(("calibrated: " + c.created_utc + " (travel map; file CRC ").c_str(), status.c_str());
  CHECK(status.find("held until the device restarts") == std::string::npos);
  CHECK(status.find("not the calibration the device was last told of") == std::string::npos);
  const std::string json = device_command_output({"status", "--device", device, "--json"}, out);
  STRCMP_CONTAINS("\"kept_through_power_off\": true", json.c_str());
  STRCMP_CONTAINS("\"parts\": \"travel map\"", json.c_str());
  // Another file than the one the device was told of is named as such.
  std::string text;
  read_calibration_file(cal, &text);
  const std::string edited = temp_path("edited.cal.json");
  FILE* f = std::fopen(edited.c_str(), "w");
  std::fputs((text + " ").c_str(), f);
  std::fclose(f);
  STRCMP_CONTAINS("not the calibration the device was last told of",
                  device_command_output({"status", "--device", device, "--calibration", edited}, out).c_str());
  // Without a settings file the simulated board starts with nothing stored.
  STRCMP_CONTAINS("calibrated: not that the device knows",
                  device_command_output({"status", "--device", "sim:part=flat"}, out).c_str());
  for (const std::string& path : {cal, cal + ".flat.scan", out, flash, edited}) std::remove(path.c_str());
}

TEST(SimCalibration, AStoredScanIsRecorrectedByANewerCalibrationAndKeepsItsRawPoints) {
  const std::string cal = calibrate(temp_path("old.cal.json")), part = temp_path("plain.scan");
  LONGS_EQUAL(0, run_scan(dome_scan("none", part)));
  const PointCloud raw = read_points(part);
  CHECK(raw.calibration.empty());
  RecorrectArgs r;
  r.scan = part;
  r.calibration = cal;
  LONGS_EQUAL(0, run_recorrect(r));
  const PointCloud corrected = read_points(part);
  const TableCalibration c = read_calibration_file(cal);
  for (size_t k = 0; k < raw.points.size(); k += 97) {
    DOUBLES_EQUAL(raw.points[k].z - c.z_error_at(raw.points[k].x, raw.points[k].y), corrected.points[k].z, 1e-6);
  }
  LONGS_EQUAL(raw.points.size(), read_scan_file(part).points.size());
  std::remove(part.c_str());
  std::remove(cal.c_str());
  std::remove((cal + ".flat.scan").c_str());
}
