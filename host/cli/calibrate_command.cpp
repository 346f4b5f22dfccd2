// Calibrating the table on a flat (guided, then scanned) and re-correcting stored scans.
#include "host/cli/calibrate_command.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "host/cli/scan_command.h"
#include "host/device/request.h"
#include "host/device/session.h"
#include "host/io/atomic_file.h"
#include "host/scan/ball_plate_calibration.h"
#include "host/scan/calibration_summary.h"
#include "host/scan/flat_calibration.h"
#include "host/scan/gauge_tilt_calibration.h"
#include "host/scan/step_gauge_calibration.h"
#include "host/scan/scan_file.h"
#include "host/scan/table_calibration.h"
#include "host/transport/transport.h"

namespace dg::host {

namespace {

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

}  // namespace

CLI::App* add_calibrate_command(CLI::App& app, CalibrateArgs& a) {
  CLI::App* cmd = app.add_subcommand("calibrate", "measure the table's travel error on a reference flat and write a calibration file");
  cmd->add_option("--artefact", a.artefact,
                  "flat (an optical flat or a surface plate: the travel's height error), or ballplate (balls at certified "
                  "centres: the axes' scale and squareness), stepgauge (steps of certified heights: the gauge's scale), or "
                  "sphere (a reference sphere of certified diameter: the gauge's tilt); each after the flat, added to its "
                  "calibration in -o")
      ->capture_default_str()->check(CLI::IsMember({"flat", "ballplate", "stepgauge", "sphere"}));
  cmd->add_option("--certificate", a.certificate,
                  "ballplate: the certified ball centres, CSV x_mm,y_mm; stepgauge: the steps' certified heights, one a line "
                  "in mm (matched to the steps by height)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--diameter-mm", a.diameter_mm, "sphere: its certified diameter, mm")->check(CLI::Range(1.0, 200.0));
  cmd->add_option("--sphere-at", a.sphere_at, "sphere: where its top stands on the table, X,Y in mm (within 3 mm)");
  cmd->add_option("--lead-mm", a.lead_mm,
                  "sphere: the lead screws' lead (travel per turn), mm: their periodic error is measured as well (scan at "
                  "--ball-step 0.5 or finer; before the ball plate, whose axes it then corrects)")
      ->check(CLI::Range(0.5, 100.0));
  cmd->add_option("--ball-step", a.ball_step_mm, "ballplate, stepgauge and sphere: grid step of the artefact's scan, mm")
      ->capture_default_str()->check(CLI::Range(0.05, 2.0));
  cmd->add_option("--device", a.device, "device URI (else DIGITIZER_DEVICE or the config file)");
  cmd->add_option("--x", a.x, "the travel to calibrate, x range MIN:MAX in mm (cover every scan's area)")->capture_default_str();
  cmd->add_option("--y", a.y, "y range MIN:MAX in mm")->capture_default_str();
  cmd->add_option("--step", a.step_mm, "grid step of the map, mm (5 keeps interpolation well under a micrometre on a smooth table)")
      ->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--samples", a.samples, "gauge readings averaged per point")->capture_default_str()->check(CLI::Range(1, 16));
  cmd->add_option("--flatness-um", a.flatness_um, "the flat's certified flatness, peak to valley, um (its certificate)")
      ->capture_default_str()->check(CLI::Range(0.0, 1000.0));
  cmd->add_option("--from", a.from, "make the map from this scan of the flat instead of scanning")->check(CLI::ExistingFile);
  cmd->add_option("--scan-output", a.scan_output, "keep the flat's scan here (default OUTPUT.flat.scan)");
  cmd->add_option("-o,--output", a.output, "the calibration file to write (.json)")->required();
  cmd->add_flag("--force", a.force, "replace an existing flat scan");
  cmd->add_flag("-q,--quiet", a.quiet, "print nothing but errors");
  return cmd;
}

CLI::App* add_recorrect_command(CLI::App& app, RecorrectArgs& a) {
  CLI::App* cmd = app.add_subcommand("recorrect", "correct a stored scan by another table calibration (the raw points stay in it)");
  cmd->add_option("scan", a.scan, "the scan file")->required()->check(CLI::ExistingFile);
  cmd->add_option("--calibration", a.calibration, "the calibration file now to apply")->required()->check(CLI::ExistingFile);
  return cmd;
}

int scan_artefact(const ArtefactScan& s, const std::string& what) {
  if (!s.quiet) {
    std::printf("%s; scanning x %s, y %s mm.\n", what.c_str(), s.x.c_str(), s.y.c_str());
    // A person at a terminal confirms; a script (no terminal) goes on.
    if (isatty(STDIN_FILENO) != 0) {
      std::printf("  Press Enter when it is in place (Ctrl-C to stop) ");
      std::fflush(stdout);
      std::string line;
      std::getline(std::cin, line);
    }
  }
  ScanArgs scan;
  scan.device = s.device;
  scan.x = s.x, scan.y = s.y;
  scan.step_mm = s.step_mm;
  scan.samples = s.samples;
  scan.output = s.output;
  scan.force = s.force;
  scan.quiet = s.quiet;
  scan.calibration = s.calibration;
  const int scanned = run_scan(scan);
  if (scanned != 0) {
    std::fprintf(stderr, "digitizer: the artefact's scan did not finish; nothing measured from it (the points are in %s)\n",
                 s.output.c_str());
  }
  return scanned;
}

void ranges_around(const std::vector<Point2>& points, double margin_mm, std::string* x, std::string* y) {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const Point2& p : points) x0 = std::fmin(x0, p.x), x1 = std::fmax(x1, p.x), y0 = std::fmin(y0, p.y), y1 = std::fmax(y1, p.y);
  char text[64];
  std::snprintf(text, sizeof text, "%.3f:%.3f", std::fmax(0.0, x0 - margin_mm), x1 + margin_mm);
  *x = text;
  std::snprintf(text, sizeof text, "%.3f:%.3f", std::fmax(0.0, y0 - margin_mm), y1 + margin_mm);
  *y = text;
}

namespace {

// The artefact's scan as `a` asks for it, raw (it is what the calibration is made of).
ArtefactScan raw_scan_of(const CalibrateArgs& a, const std::string& x, const std::string& y, double step_mm,
                         const std::string& path) {
  ArtefactScan s;
  s.device = a.device, s.x = x, s.y = y, s.step_mm = step_mm, s.samples = a.samples, s.output = path;
  s.force = a.force, s.quiet = a.quiet;
  return s;
}

PointCloud raw_points(const std::string& path) {
  if (read_scan_file(path).calibration_json) {
    throw CalibrationError(path + ": this scan is corrected by a calibration already; calibrate from a raw scan of the artefact");
  }
  return read_points(path);
}

int calibrate_flat(const CalibrateArgs& a) {
  std::string flat_scan = a.from;
  if (flat_scan.empty()) {
    flat_scan = a.scan_output.empty() ? a.output + ".flat.scan" : a.scan_output;
    const int scanned = scan_artefact(raw_scan_of(a, a.x, a.y, a.step_mm, flat_scan),
                                      "Calibrating on a flat (an optical flat or a ground surface plate, larger than the "
                                      "area), clamped clean and roughly level, the gauge on it near mid-travel");
    if (scanned != 0) return scanned;
  }
  const ScanData raw = read_scan_file(flat_scan);
  TableCalibration c = calibrate_from_flat(raw_points(flat_scan), a.flatness_um * 1e-3, flat_scan);
  c.created_utc = utc_now();
  if (raw.device) c.device_id = raw.device->device_id;
  double largest = 0, u_max = 0;
  for (size_t k = 0; k < c.z_error_mm.size(); ++k) {
    largest = std::fmax(largest, std::fabs(c.z_error_mm[k]));
    u_max = std::fmax(u_max, c.u_mm[k]);
  }
  write_file_atomically(a.output, calibration_to_json(c));
  if (!a.quiet) {
    std::printf("travel height error over x %.3f..%.3f, y %.3f..%.3f mm (%zu x %zu nodes, %zu readings): up to %.4f mm\n",
                c.x0_mm, c.x1_mm(), c.y0_mm, c.y1_mm(), c.nx, c.ny, c.points, largest);
    std::printf("the flat's plane taken out: z = %.4f %+.6f x %+.6f y mm (its setup on the table, not the machine's)\n",
                c.plane_mm[0], c.plane_mm[1], c.plane_mm[2]);
    std::printf("gauge noise %.4f mm; map uncertainty u <= %.4f mm (k = 1), U <= %.4f mm (k = 2); readings off the map: RMS %.4f mm\n",
                c.noise_mm, u_max, 2 * u_max, c.residual_rms_mm);
    std::printf("wrote %s; scan with --calibration %s (or `calibration = %s` in the config file)\n", a.output.c_str(),
                a.output.c_str(), a.output.c_str());
  }
  return 0;
}

// An artefact's readings for the ball plate or the sphere: scanned raw at --ball-step over x, y
// (kept in --scan-output, else OUTPUT + suffix) unless --from names a scan, from the device the
// calibration was measured on, corrected by `correct_by`. exit_code is run_scan's when the scan
// did not finish.
struct ArtefactPoints {
  int exit_code = 0;
  std::string scan;
  PointCloud points;
};

ArtefactPoints artefact_points(const CalibrateArgs& a, const TableCalibration& correct_by, const std::string& x,
                               const std::string& y, const char* suffix, const std::string& prompt) {
  ArtefactPoints out;
  out.scan = a.from;
  if (out.scan.empty()) {
    out.scan = a.scan_output.empty() ? a.output + suffix : a.scan_output;
    out.exit_code = scan_artefact(raw_scan_of(a, x, y, a.ball_step_mm, out.scan), prompt);
    if (out.exit_code != 0) return out;
  }
  const ScanData raw = read_scan_file(out.scan);
  if (raw.device) check_calibration_device(correct_by.device_id, a.output, raw.device->device_id);
  out.points = raw_points(out.scan);
  apply_calibration(correct_by, out.points, out.scan);
  return out;
}

// The calibration the ball plate or the sphere adds to: the flat's, in -o.
TableCalibration existing_calibration(const CalibrateArgs& a, const char* adds) {
  struct stat existing {};
  if (::stat(a.output.c_str(), &existing) != 0) {
    throw CalibrationError(a.output + ": no calibration there; calibrate on a flat first (-o the same file): the " + a.artefact +
                           " adds " + adds + " to the travel's map");
  }
  return read_calibration_file(a.output);
}

int calibrate_ball_plate(const CalibrateArgs& a) {
  if (a.certificate.empty()) throw std::invalid_argument("--artefact ballplate needs --certificate, the balls' certified centres");
  // The axes are added to the travel's map: the flat comes first, and its file is -o.
  TableCalibration c = existing_calibration(a, "the axes' scale and squareness");
  const std::vector<Point2> certified = read_ball_certificate(a.certificate);
  std::string x, y;
  ranges_around(certified, 9.0, &x, &y);  // each ball's footprint and the plate's placement error
  // The travel's height error tilts each ball's cap by the map's local slope and shifts its fitted
  // centre by the ball's radius times that slope (3.6 um for 30 um over 50 mm): the map comes out
  // first. An earlier ball plate's axes do not apply: they are what is measured again.
  TableCalibration without_axes = c;
  without_axes.has_axes = false;
  const ArtefactPoints plate = artefact_points(a, without_axes, x, y, ".ballplate.scan",
                                               "Calibrating on a ball plate, laid with its frame on the table's (its first ball "
                                               "within 2 mm of its certified place, its rows along x), the gauge over it");
  if (plate.exit_code != 0) return plate.exit_code;
  const AxisCalibration axes = calibrate_from_ball_plate(plate.points, certified, plate.scan);
  c.has_axes = true;
  c.scale_x_ppm = axes.scale_x_ppm, c.scale_y_ppm = axes.scale_y_ppm, c.squareness_urad = axes.squareness_urad;
  c.u_scale_x_ppm = axes.u_scale_x_ppm, c.u_scale_y_ppm = axes.u_scale_y_ppm, c.u_squareness_urad = axes.u_squareness_urad;
  c.straightness = axes.straightness;
  c.balls = axes.centres.size();
  c.ball_centre_rms_mm = axes.centre_rms_mm;
  c.axes_with_lead = c.lead.measured;
  c.axes_created_utc = utc_now();
  write_file_atomically(a.output, calibration_to_json(c));
  if (!a.quiet) {
    std::printf("%zu balls fitted; their centres match the certificate within %.4f mm RMS after the fit\n", c.balls,
                c.ball_centre_rms_mm);
    std::printf("scale x %+.1f ppm (u %.1f), scale y %+.1f ppm (u %.1f), squareness %+.1f urad (u %.1f); the plate lay "
                "%.3f degrees off the x axis\n",
                c.scale_x_ppm, c.u_scale_x_ppm, c.scale_y_ppm, c.u_scale_y_ppm, c.squareness_urad, c.u_squareness_urad,
                axes.placement_deg);
    const Straightness& bow = c.straightness;
    if (bow.measured) {
      std::printf("straightness: the y way bows %+.2f um in x over y %.1f..%.1f mm (u %.2f), the x way %+.2f um in y over "
                  "x %.1f..%.1f mm (u %.2f)\n",
                  bow.x_um, bow.centre_y_mm - bow.half_span_y_mm, bow.centre_y_mm + bow.half_span_y_mm, bow.u_x_um, bow.y_um,
                  bow.centre_x_mm - bow.half_span_x_mm, bow.centre_x_mm + bow.half_span_x_mm, bow.u_y_um);
    } else {
      std::printf("straightness: not measured (the plate needs three rows and three columns of balls)\n");
    }
    std::printf("added to %s: scans corrected by it now have their x and y corrected too\n", a.output.c_str());
  }
  return 0;
}

Point2 sphere_position(const std::string& text) {
  Point2 at{};
  char comma = 0, extra = 0;
  std::istringstream fields(text);
  if (!(fields >> at.x >> comma >> at.y) || comma != ',' || (fields >> extra) || !std::isfinite(at.x) || !std::isfinite(at.y)) {
    throw std::invalid_argument("--sphere-at must be X,Y in mm (where the sphere's top stands), got '" + text + "'");
  }
  return at;
}

int calibrate_sphere(const CalibrateArgs& a) {
  if (!(a.diameter_mm > 0)) throw std::invalid_argument("--artefact sphere needs --diameter-mm, the sphere's certified diameter");
  if (a.sphere_at.empty()) throw std::invalid_argument("--artefact sphere needs --sphere-at X,Y, where the sphere's top stands");
  // Fewer than four readings a turn cannot tell the screw's sine from its cosine, or from a
  // shorter lead's alias: refused before the table moves.
  if (a.lead_mm > 0 && a.from.empty() && a.ball_step_mm > a.lead_mm / 4) {
    char words[200];
    std::snprintf(words, sizeof words, "--lead-mm %g needs the sphere scanned at a quarter of the lead or finer: --ball-step %g or less "
                  "(it is %g)", a.lead_mm, a.lead_mm / 4, a.ball_step_mm);
    throw std::invalid_argument(words);
  }
  const Point2 at = sphere_position(a.sphere_at);
  TableCalibration c = existing_calibration(a, "the gauge's tilt");
  // The cap the fit uses (55 degrees from the top) and 3 mm for where the sphere was said to be.
  std::string x, y;
  ranges_around({at}, sphere_cap_reach_mm(a.diameter_mm) + 3.0, &x, &y);
  // The map and the axes come out first: the travel's slope under the sphere tilts its cap as the
  // gauge's lean would, and the axes' scale stretches it. An earlier tilt does not apply: it is
  // what is measured again, and so is the screws' error when a lead is given (else an earlier one
  // corrects the readings).
  TableCalibration without_tilt = c;
  without_tilt.has_gauge_tilt = false;
  if (a.lead_mm > 0) without_tilt.lead = LeadError{};
  const ArtefactPoints sphere = artefact_points(a, without_tilt, x, y, ".sphere.scan",
                                                "Calibrating the gauge's tilt on a reference sphere, fixed on its stem with its "
                                                "top under the gauge at the given place, the gauge clamped as it will measure");
  if (sphere.exit_code != 0) return sphere.exit_code;
  const GaugeTilt tilt = calibrate_gauge_tilt(sphere.points, a.diameter_mm, sphere.scan, &c, a.lead_mm);
  c.has_gauge_tilt = true;
  c.gauge_tilt_x_urad = tilt.tilt_x_urad, c.gauge_tilt_y_urad = tilt.tilt_y_urad;
  c.u_gauge_tilt_x_urad = tilt.u_tilt_x_urad, c.u_gauge_tilt_y_urad = tilt.u_tilt_y_urad;
  // A ball plate measured before the screws' error was corrected took its balls' periodic shifts
  // for scale, squareness and bow: those axes would be false, so they go, with the reason. (A plate
  // measured under an earlier lead correction stays: a new measurement moves it by its noise.)
  bool axes_dropped = false;
  if (tilt.lead.measured) {
    c.lead = tilt.lead;
    if (c.has_axes && !c.axes_with_lead) {
      axes_dropped = true;
      c.has_axes = false;
      c.straightness = Straightness{};
    }
  }
  c.sphere_diameter_mm = a.diameter_mm;
  c.sphere_points = tilt.points;
  c.sphere_rms_mm = tilt.residual_rms_mm;
  c.gauge_created_utc = utc_now();
  write_file_atomically(a.output, calibration_to_json(c));
  if (!a.quiet) {
    const double lean_urad = std::hypot(tilt.tilt_x_urad, tilt.tilt_y_urad);
    std::printf("%zu readings on the sphere's cap fitted within %.4f mm RMS (its readings alone give %.4f mm across; certified "
                "%.4f)\n", tilt.points, tilt.residual_rms_mm, tilt.free_diameter_mm, a.diameter_mm);
    std::printf("gauge tilt x %+.0f urad (u %.0f), y %+.0f urad (u %.0f): it leans %.3f degrees, so a reading 10 mm up lies "
                "%.1f um to the side\n", tilt.tilt_x_urad, tilt.u_tilt_x_urad, tilt.tilt_y_urad, tilt.u_tilt_y_urad,
                lean_urad * 1e-6 * 57.29577951308232, lean_urad * 1e-6 * 10 * 1e3);
    std::printf("  of u: the readings' scatter %.0f and %.0f urad, the travel map's uncertainty under the sphere %.0f and %.0f urad\n",
                tilt.u_noise_x_urad, tilt.u_noise_y_urad, tilt.u_map_x_urad, tilt.u_map_y_urad);
    if (tilt.lead.measured) {
      const LeadError& e = tilt.lead;
      std::printf("lead screws (%.2f mm a turn): periodic error %.2f um in x (u %.2f), %.2f um in y (u %.2f) at its largest\n",
                  e.lead_mm, e.amplitude_x_um(), e.u_x_um, e.amplitude_y_um(), e.u_y_um);
    }
    std::printf("added to %s: scans corrected by it now have the gauge's lean%s taken out\n", a.output.c_str(),
                tilt.lead.measured ? " and the screws' periodic error" : "");
  }
  if (axes_dropped) {
    std::fprintf(stderr, "digitizer: %s: the ball plate's axes were measured without this periodic correction and are "
                 "removed; calibrate the ball plate again (-o the same file)\n", a.output.c_str());
  }
  return 0;
}

int calibrate_step_gauge(const CalibrateArgs& a) {
  if (a.certificate.empty()) throw std::invalid_argument("--artefact stepgauge needs --certificate, the steps' certified heights");
  const std::vector<double> certified = read_step_certificate(a.certificate);
  TableCalibration c = existing_calibration(a, "the gauge's scale");
  // Everything else comes out first (the map's slope would tilt a top); an earlier scale does not
  // apply: it is what is measured again.
  TableCalibration without_scale = c;
  without_scale.has_gauge_scale = false;
  const ArtefactPoints steps = artefact_points(a, without_scale, a.x, a.y, ".stepgauge.scan",
                                               "Calibrating the gauge's scale on a step gauge, the scan (--x, --y) over its "
                                               "tops and the plate beside them");
  if (steps.exit_code != 0) return steps.exit_code;
  const GaugeScale scale = calibrate_gauge_scale(steps.points, certified, steps.scan, &c);
  c.has_gauge_scale = true;
  c.gauge_scale_ppm = scale.scale_ppm, c.u_gauge_scale_ppm = scale.u_scale_ppm;
  c.scale_steps = scale.steps.size();
  c.scale_rms_mm = scale.residual_rms_mm;
  c.scale_created_utc = utc_now();
  write_file_atomically(a.output, calibration_to_json(c));
  if (!a.quiet) {
    for (size_t k = 0; k < scale.steps.size(); ++k) {
      std::printf("step %zu at (%.1f, %.1f) mm: %.4f mm above the plate (u %.4f, %zu readings), certified %.4f\n", k + 1,
                  scale.steps[k].x_mm, scale.steps[k].y_mm, scale.steps[k].height_mm, scale.steps[k].u_mm, scale.steps[k].points,
                  certified[k]);
    }
    const double span = std::fabs(certified.back() - certified.front());
    std::printf("gauge scale %+.0f ppm (u %.0f): over the steps' %.1f mm it reads %+.2f um; heights off the line %.4f mm RMS\n",
                scale.scale_ppm, scale.u_scale_ppm, span, scale.scale_ppm * 1e-6 * span * 1e3, scale.residual_rms_mm);
    std::printf("added to %s: scans corrected by it now have their heights rescaled\n", a.output.c_str());
  }
  return 0;
}

}  // namespace

namespace {

// Tells the device what the file now holds and when it was measured, so that `status` on any host
// says whether and when it was calibrated. The calibration is written already: a device that cannot
// keep the summary, or is gone, is told of in a note, not an error. A calibration from stored scans
// (--from) has no device to tell.
void keep_summary_on_device(const CalibrateArgs& a) {
  if (!a.from.empty() || a.device.empty()) return;
  std::string text;
  const TableCalibration c = read_calibration_file(a.output, &text);
  digitizer_Envelope message = digitizer_Envelope_init_zero;
  message.which_body = digitizer_Envelope_command_tag;
  message.body.command.kind = digitizer_CommandKind_CMD_SET_CALIBRATION;
  message.body.command.has_calibration = true;
  message.body.command.calibration = summarize_calibration(c, text);
  try {
    auto transport = open_transport(a.device);
    Session session(*transport);
    const digitizer_Hello hello = session.hello(5000);
    if ((hello.capabilities & digitizer_Capability_CAP_CALIBRATION_SUMMARY) == 0) {
      if (!a.quiet) std::printf("note: device %s keeps no calibration summary (older firmware)\n", hello.device_id);
      return;
    }
    request(session, message, 5000);
    digitizer_Envelope status = digitizer_Envelope_init_zero;
    status.which_body = digitizer_Envelope_command_tag;
    status.body.command.kind = digitizer_CommandKind_CMD_STATUS;
    const digitizer_Envelope reply = request(session, status, 5000);
    session.flush(1000);
    if (!a.quiet) {
      const bool kept = reply.which_body == digitizer_Envelope_status_tag && reply.body.status.calibration_kept;
      std::printf("device %s now says it was calibrated %s (%s)%s\n", hello.device_id,
                  unix_to_utc(message.body.command.calibration.created_unix_s).c_str(),
                  calibration_parts_text(message.body.command.calibration.parts).c_str(),
                  kept ? ", kept through a power-off" : "; it holds that until it restarts (the board stores no settings)");
    }
  } catch (const std::exception& error) {
    std::fprintf(stderr, "digitizer: note: %s is written, but the device was not told of it: %s\n", a.output.c_str(), error.what());
  }
}

}  // namespace

int run_calibrate(const CalibrateArgs& a) {
  int result = 0;
  if (a.artefact == "ballplate") {
    result = calibrate_ball_plate(a);
  } else if (a.artefact == "stepgauge") {
    result = calibrate_step_gauge(a);
  } else if (a.artefact == "sphere") {
    result = calibrate_sphere(a);
  } else {
    result = calibrate_flat(a);
  }
  if (result == 0) keep_summary_on_device(a);
  return result;
}

int run_recorrect(const RecorrectArgs& a) {
  std::string json;
  const TableCalibration c = read_calibration_file(a.calibration, &json);
  const ScanData scan = read_scan_file(a.scan);
  if (scan.device) check_calibration_device(c.device_id, a.calibration, scan.device->device_id);
  ScanData check = scan;
  check.calibration_json = json;
  correct_by_record(check, nullptr, a.scan);  // throws, naming the point, if the map does not cover the scan
  ScanFileWriter file = ScanFileWriter::continue_file(a.scan, scan.complete_bytes);
  file.append_calibration(json);
  file.sync();
  std::printf("%s: its %zu points are now corrected by %s (measured %s)%s\n", a.scan.c_str(), scan.points.size(),
              a.calibration.c_str(), c.created_utc.empty() ? "at an unknown time" : c.created_utc.c_str(),
              scan.calibration_json ? "; the earlier calibration's record stays in the file, unused" : "");
  return 0;
}

}  // namespace dg::host
