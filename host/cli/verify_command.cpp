// Verifying the table on a ball plate or a step gauge: scan it corrected, measure its ball-to-ball
// lengths or step-to-step heights, report E.
#include "host/cli/verify_command.h"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "host/cli/calibrate_command.h"
#include "host/io/atomic_file.h"
#include "host/scan/ball_plate_calibration.h"
#include "host/scan/length_verification.h"
#include "host/scan/step_gauge_calibration.h"
#include "host/scan/table_calibration.h"

namespace dg::host {

namespace {

// "a,b[,c]" as numbers; throws std::invalid_argument naming the option.
std::vector<double> numbers(const std::string& text, size_t count, const char* option) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ',')) {
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != part.size() || !std::isfinite(v)) {
      throw std::invalid_argument(std::string(option) + ": '" + part + "' is not a number");
    }
    out.push_back(v);
  }
  if (out.size() != count) throw std::invalid_argument(std::string(option) + " takes " + std::to_string(count) + " numbers, got '" + text + "'");
  return out;
}

// E against L, the +-E_MPE lines and zero, in SVG: what a person looks at to see whether the errors
// grow with length (scale) or scatter (noise).
std::string errors_svg(const LengthVerification& v, const PermissibleError& mpe, const std::string& title) {
  double l_max = 0, e_max = 0;
  for (const MeasuredLength& l : v.lengths) l_max = std::fmax(l_max, l.certified_mm), e_max = std::fmax(e_max, std::fabs(l.error_mm()));
  l_max = std::ceil(l_max / 10) * 10;
  const double e_top = std::fmax(e_max, mpe.at_mm(l_max)) * 1.2e3;  // um
  const double w = 640, h = 400, left = 70, right = 20, top = 40, bottom = 50;
  auto px = [&](double l_mm) { return left + (w - left - right) * l_mm / l_max; };
  auto py = [&](double e_um) { return top + (h - top - bottom) * (0.5 - 0.5 * e_um / e_top); };
  std::string s;
  char line[400];
  std::snprintf(line, sizeof line, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" font-family=\"sans-serif\" font-size=\"13\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n", w, h);
  s += line;
  std::snprintf(line, sizeof line, "<text x=\"%.0f\" y=\"22\" font-size=\"15\">%s</text>\n", left, title.c_str());
  s += line;
  std::snprintf(line, sizeof line, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#888\"/>\n", px(0), py(0), px(l_max), py(0));
  s += line;
  for (int sign : {1, -1}) {
    std::snprintf(line, sizeof line, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#c0392b\" stroke-width=\"2\" stroke-dasharray=\"6 4\"/>\n",
                  px(0), py(sign * mpe.at_mm(0) * 1e3), px(l_max), py(sign * mpe.at_mm(l_max) * 1e3));
    s += line;
  }
  for (const MeasuredLength& l : v.lengths) {
    const bool ok = std::fabs(l.error_mm()) <= mpe.at_mm(l.certified_mm);
    std::snprintf(line, sizeof line, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"%s\"/>\n", px(l.certified_mm), py(l.error_mm() * 1e3),
                  ok ? "#2471a3" : "#c0392b");
    s += line;
  }
  for (int k = 0; k <= 4; ++k) {
    const double l = l_max * k / 4, e = e_top * (k - 2) / 2;
    std::snprintf(line, sizeof line, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%.0f</text>\n<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%.1f</text>\n",
                  px(l), h - bottom + 18, l, left - 6, py(e) + 4, std::fabs(e) < 1e-9 ? 0.0 : e);
    s += line;
  }
  std::snprintf(line, sizeof line, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">length L, mm</text>\n"
                "<text x=\"16\" y=\"%.1f\" transform=\"rotate(-90 16 %.1f)\" text-anchor=\"middle\">error E, um (dashed: E_MPE = %g + L/%g um)</text>\n</svg>\n",
                0.5 * (px(0) + px(l_max)), h - 12, 0.5 * h, 0.5 * h, mpe.a_um, mpe.k);
  s += line;
  return s;
}

}  // namespace

CLI::App* add_verify_command(CLI::App& app, VerifyArgs& a) {
  CLI::App* cmd = app.add_subcommand("verify", "measure a ball plate's lengths or a step gauge's heights and report the "
                                                "length-measurement error E against E_MPE");
  cmd->add_option("--artefact", a.artefact, "ballplate (lengths in the table's plane) or stepgauge (heights along z)")
      ->capture_default_str()->check(CLI::IsMember({"ballplate", "stepgauge"}));
  cmd->add_option("--device", a.device, "device URI (else DIGITIZER_DEVICE or the config file)");
  cmd->add_option("--certificate", a.certificate,
                  "ballplate: the certified ball centres, CSV x_mm,y_mm; stepgauge: the steps' certified heights, one a line in mm")
      ->required()->check(CLI::ExistingFile);
  cmd->add_option("--x", a.x, "stepgauge: the area to scan, x range MIN:MAX in mm (its tops and the plate beside them)");
  cmd->add_option("--y", a.y, "stepgauge: y range MIN:MAX in mm");
  cmd->add_option("--at", a.at, "where the plate lies: its origin X,Y in mm and its turn from the table's x axis in degrees")
      ->capture_default_str();
  cmd->add_option("--mpe", a.mpe, "the maximum permissible error E_MPE = A + L/K um, as A,K")->capture_default_str();
  cmd->add_option("--shortest", a.shortest_mm, "leave out lengths shorter than this, mm")->check(CLI::Range(0.0, 10000.0));
  cmd->add_option("--ball-step", a.ball_step_mm, "grid step of the artefact's scan, mm")->capture_default_str()->check(CLI::Range(0.05, 2.0));
  cmd->add_option("--calibration", a.calibration, "the table calibration the plate's scan is corrected by (none: the table as it is)")
      ->required();
  cmd->add_option("--from", a.from, "a stored scan of the artefact instead of scanning")->check(CLI::ExistingFile);
  cmd->add_option("--scan-output", a.scan_output, "keep the artefact's scan here (default OUTPUT.scan)");
  cmd->add_option("-o,--output", a.output, "every length (or height), its certified and measured value, E and E_MPE (.csv)")->required();
  cmd->add_option("--svg", a.svg, "a picture of E against L with the E_MPE lines");
  cmd->add_flag("--force", a.force, "replace an existing plate scan");
  cmd->add_flag("-q,--quiet", a.quiet, "print nothing but errors");
  return cmd;
}

namespace {

// The lengths as CSV, the picture, the summary line; the exit code.
int report(const VerifyArgs& a, const LengthVerification& v, const PermissibleError& mpe, const std::string& title) {
  std::string csv = "from,to,certified_mm,measured_mm,error_um,mpe_um,within\n";
  char line[200];
  double shortest = 1e300, longest = 0;
  for (const MeasuredLength& l : v.lengths) {
    const bool ok = std::fabs(l.error_mm()) <= mpe.at_mm(l.certified_mm);
    std::snprintf(line, sizeof line, "%zu,%zu,%.4f,%.4f,%.2f,%.2f,%s\n", l.from + 1, l.to + 1, l.certified_mm, l.measured_mm,
                  l.error_mm() * 1e3, mpe.at_mm(l.certified_mm) * 1e3, ok ? "yes" : "no");
    csv += line;
    shortest = std::fmin(shortest, l.certified_mm), longest = std::fmax(longest, l.certified_mm);
  }
  write_file_atomically(a.output, csv);
  const std::string verdict = title + ": " + (v.pass ? "PASS" : "FAIL");
  if (!a.svg.empty()) write_file_atomically(a.svg, errors_svg(v, mpe, verdict));
  if (!a.quiet) {
    std::printf("%zu %s %.3f..%.3f mm; worst |E| %.2f um, %.0f %% of its E_MPE = %g + L/%g um: %s\n", v.lengths.size(),
                a.artefact == "stepgauge" ? "heights" : "lengths", shortest, longest, v.worst_error_mm * 1e3, v.worst_share * 100,
                mpe.a_um, mpe.k, v.pass ? "PASS" : "FAIL");
    std::printf("wrote %s%s%s\n", a.output.c_str(), a.svg.empty() ? "" : " and ", a.svg.c_str());
  }
  return v.pass ? 0 : kExitVerifyFailed;
}

// The artefact's scan, corrected by --calibration: taken unless --from names one.
std::string scanned(const VerifyArgs& a, const std::string& x, const std::string& y, const std::string& what, int* exit_code) {
  std::string path = a.from;
  if (path.empty()) {
    ArtefactScan scan;
    scan.x = x, scan.y = y;
    path = a.scan_output.empty() ? a.output + ".scan" : a.scan_output;
    scan.device = a.device, scan.step_mm = a.ball_step_mm, scan.calibration = a.calibration, scan.output = path;
    scan.force = a.force, scan.quiet = a.quiet;
    *exit_code = scan_artefact(scan, what);
  }
  return path;
}

PointCloud corrected_points(const VerifyArgs& a, const std::string& path) {
  PointCloud points = read_points(path);
  if (!a.quiet && a.calibration != "none" && points.calibration.empty()) {
    std::printf("note: %s carries no calibration record: the table is verified as it is\n", path.c_str());
  }
  return points;
}

int verify_step_gauge(const VerifyArgs& a, const PermissibleError& mpe) {
  if (a.x.empty() || a.y.empty()) throw std::invalid_argument("--artefact stepgauge needs --x and --y: its tops and the plate beside them");
  const std::vector<double> certified = read_step_certificate(a.certificate);
  int exit_code = 0;
  const std::string path = scanned(a, a.x, a.y, "Verifying heights on a step gauge, its tops and the plate beside them in x " + a.x +
                                                    ", y " + a.y, &exit_code);
  if (exit_code != 0) return exit_code;
  const LengthVerification v = verify_heights(measure_steps(corrected_points(a, path), certified, path), certified, mpe, a.shortest_mm);
  if (v.lengths.empty()) throw CalibrationError(path + ": no two steps differ enough in height to test one");
  return report(a, v, mpe, "Height error on a step gauge in x " + a.x + ", y " + a.y);
}

}  // namespace

int run_verify(const VerifyArgs& a) {
  const std::vector<double> mpe_numbers = numbers(a.mpe, 2, "--mpe");
  if (!(mpe_numbers[0] > 0) || !(mpe_numbers[1] > 0)) throw std::invalid_argument("--mpe: A and K must be positive");
  const PermissibleError mpe{mpe_numbers[0], mpe_numbers[1]};
  if (a.artefact == "stepgauge") return verify_step_gauge(a, mpe);
  const std::vector<double> at = numbers(a.at, 3, "--at");
  const std::vector<Point2> certified = read_ball_certificate(a.certificate);
  std::string x, y;
  ranges_around(placed_centres(certified, at[0], at[1], at[2]), 9.0, &x, &y);
  char what[160];
  std::snprintf(what, sizeof what, "Verifying on a ball plate laid with its origin at (%g, %g) mm, turned %g degrees", at[0], at[1], at[2]);
  int exit_code = 0;
  const std::string path = scanned(a, x, y, what, &exit_code);
  if (exit_code != 0) return exit_code;
  const LengthVerification v = verify_lengths(corrected_points(a, path), certified, at[0], at[1], at[2], mpe, a.shortest_mm, path);
  char title[160];
  std::snprintf(title, sizeof title, "Length error on a ball plate at (%g, %g) mm, %g deg", at[0], at[1], at[2]);
  return report(a, v, mpe, title);
}

}  // namespace dg::host
