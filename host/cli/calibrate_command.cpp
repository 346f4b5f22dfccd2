// Calibrating the table on a flat (guided, then scanned) and re-correcting stored scans.
#include "host/cli/calibrate_command.h"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <iostream>

#include "host/cli/scan_command.h"
#include "host/io/atomic_file.h"
#include "host/io/whole_file.h"
#include "host/scan/flat_calibration.h"
#include "host/scan/scan_file.h"
#include "host/scan/table_calibration.h"

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
  cmd->add_option("--artefact", a.artefact, "the reference artefact: flat (an optical flat or a surface plate)")
      ->capture_default_str()->check(CLI::IsMember({"flat"}));
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

int run_calibrate(const CalibrateArgs& a) {
  std::string flat_scan = a.from;
  if (flat_scan.empty()) {
    flat_scan = a.scan_output.empty() ? a.output + ".flat.scan" : a.scan_output;
    if (!a.quiet) {
      std::printf("Calibrating the table's travel over x %s, y %s mm on a flat.\n"
                  "  Clamp the flat (an optical flat or a ground surface plate, larger than that area) on the table,\n"
                  "  clean, roughly level; set the gauge on it near mid-travel, with room to move both ways.\n",
                  a.x.c_str(), a.y.c_str());
      // A person at a terminal confirms; a script (no terminal) goes on.
      if (isatty(STDIN_FILENO) != 0) {
        std::printf("  Press Enter when the flat is in place (Ctrl-C to stop) ");
        std::fflush(stdout);
        std::string line;
        std::getline(std::cin, line);
      }
    }
    ScanArgs scan;
    scan.device = a.device;
    scan.x = a.x, scan.y = a.y;
    scan.step_mm = a.step_mm;
    scan.samples = a.samples;
    scan.output = flat_scan;
    scan.force = a.force;
    scan.quiet = a.quiet;
    scan.calibration = "none";  // the flat is measured raw: it is what the map is made of
    const int scanned = run_scan(scan);
    if (scanned != 0) {
      std::fprintf(stderr, "digitizer: the flat's scan did not finish; no calibration written (the points are in %s)\n", flat_scan.c_str());
      return scanned;
    }
  }
  const ScanData raw = read_scan_file(flat_scan);
  if (raw.calibration_json) {
    throw CalibrationError(flat_scan + ": this scan is corrected by a calibration already; calibrate from a raw scan of the flat");
  }
  const PointCloud points = read_points(flat_scan);
  TableCalibration c = calibrate_from_flat(points, a.flatness_um * 1e-3, flat_scan);
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

int run_recorrect(const RecorrectArgs& a) {
  std::string json;
  if (!read_whole_file(a.calibration, &json)) throw CalibrationError(a.calibration + ": cannot open: " + std::strerror(errno));
  const TableCalibration c = calibration_from_json(json, a.calibration);
  const ScanData scan = read_scan_file(a.scan);
  PointCloud check;
  for (const PointSample& p : scan.points) check.points.push_back({p.x_nm * 1e-6, p.y_nm * 1e-6, p.z_nm * 1e-6});
  apply_calibration(c, check, a.scan);  // throws, naming the point, if the map does not cover the scan
  ScanFileWriter file = ScanFileWriter::continue_file(a.scan, scan.complete_bytes);
  file.append_calibration(json);
  file.sync();
  std::printf("%s: its %zu points are now corrected by %s (measured %s)%s\n", a.scan.c_str(), scan.points.size(),
              a.calibration.c_str(), c.created_utc.empty() ? "at an unknown time" : c.created_utc.c_str(),
              scan.calibration_json ? "; the earlier calibration's record stays in the file, unused" : "");
  return 0;
}

}  // namespace dg::host
