// The scan command: identify, request (or resume), capture with progress, summarise.
#include "host/cli/scan_command.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <csignal>
#include <cstdio>
#include <optional>
#include <random>

#include "common/proto/scan_grid.h"
#include "host/cli/adaptive_scan.h"
#include "host/cli/progress.h"
#include "host/cli/units.h"
#include "host/device/capture.h"
#include "host/device/pull_fit.h"
#include "host/device/repeatability.h"
#include "host/fit/device_fit_surface.h"
#include "host/fit/propagated_uncertainty.h"
#include "host/scan/drift_removal.h"
#include "host/scan/fly_correction.h"
#include "host/scan/point_reader.h"
#include "host/scan/table_calibration.h"
#include "host/cad/surface_json.h"
#include "host/transport/transport.h"

namespace dg::host {

namespace {

volatile std::sig_atomic_t g_interrupted = 0;

void on_interrupt(int) { g_interrupted = 1; }

// Pulls the device's fit of its latest scan and writes it as SURF.json. With the scan's file
// (`scan_path`), the fit gains a report from the scan's points: their distances to it and the
// surface's standard uncertainty.
void write_device_fit(Session& session, const digitizer_Hello& device, const std::string& model,
                      const std::string& path, bool quiet, const std::string& scan_path) {
  const digitizer_DeviceFitModel which =
      model == "bspline" ? digitizer_DeviceFitModel_DEVICE_FIT_NET : digitizer_DeviceFitModel_DEVICE_FIT_BEZIER;
  const digitizer_FitResult fit = pull_fit(session, device, which, 5000);
  const std::string source = std::string("device ") + device.device_id + " scan " + std::to_string(fit.scan_id);
  FittedSurface surface = surface_from_device_fit(fit, source);
  std::string why_no_uncertainty = "no scan file given (--scan)";
  if (!scan_path.empty()) {
    const ScanData data = read_scan_file(scan_path);
    if (!data.request || data.request->scan_id != fit.scan_id) {
      throw std::runtime_error(scan_path + " holds " + (data.request ? "scan " + std::to_string(data.request->scan_id) : "no scan") +
                               ", the device's fit is of scan " + std::to_string(fit.scan_id));
    }
    // The device fitted the points as it measured them: its report is against those.
    why_no_uncertainty = add_scan_to_device_fit(surface, read_points(scan_path, true), fit.points, fit.rejected);
    if (data.calibration_json && !quiet) {
      std::printf("note: the device fitted the points as measured; the table calibration corrects the scan's points, not "
                  "its surface (fit the scan on the host for a corrected one)\n");
    }
  }
  write_surface_json(path, surface);
  if (!quiet) {
    std::printf("device fit: %s, %u x %u control points from %u points (%u rejected)%s\n", surface.model.c_str(),
                fit.side, fit.side, fit.points, fit.rejected, fit.scan_finished ? "" : ", scan still running");
    if (surface.has_fit) {
      std::printf("  the scan's points to it: rms %.4f max |d| %.4f mm (orthogonal)\n", surface.distance.rms,
                  surface.distance.max_abs);
    }
    const SurfaceUncertainty& u = surface.uncertainty;
    if (u.computed) {
      std::printf("  standard uncertainty u (k = 1): max %.4f mean %.4f mm; expanded U = 2u: max %.4f mm, from a point "
                  "uncertainty of %.4f mm\n", u.max_mm, u.mean_mm, 2 * u.max_mm, u.sigma_mm);
    } else {
      std::printf("  standard uncertainty: not stated: %s\n", why_no_uncertainty.c_str());
    }
    std::printf("wrote %s\n", path.c_str());
  }
}

digitizer_ScanRequest request_from(const ScanArgs& a) {
  digitizer_ScanRequest request = digitizer_ScanRequest_init_zero;
  // A scan id that another scan is unlikely to share, so a resume finds this scan and no other.
  std::random_device entropy;
  request.scan_id = (entropy() & 0x7fffffffu) | 1u;
  request.has_x = request.has_y = true;
  const RangeNm x = parse_range_mm(a.x, "--x");
  const RangeNm y = parse_range_mm(a.y, "--y");
  request.x.min_nm = x.min_nm;
  request.x.max_nm = x.max_nm;
  request.y.min_nm = y.min_nm;
  request.y.max_nm = y.max_nm;
  const int32_t step = mm_to_nm(a.step_mm, "--step");
  const int32_t step_y = a.step_y_mm > 0 ? mm_to_nm(a.step_y_mm, "--step-y") : step;
  if (step <= 0 || step_y <= 0) throw std::invalid_argument("--step must be > 0");
  // A step longer than its range gives one point per line (or one line) and looks like a scan
  // that ran: refused, naming both. A range of one position (--y 10:10) takes any step.
  auto within = [](int64_t step_nm, const RangeNm& range, const char* step_name, const char* range_name, const std::string& text,
                   const char* one) {
    const int64_t span_nm = static_cast<int64_t>(range.max_nm) - range.min_nm;
    if (span_nm > 0 && step_nm > span_nm) {
      char why[200];
      std::snprintf(why, sizeof why, "%s %.4g mm is longer than the %s range %s (%.4g mm): the scan would measure one %s there",
                    step_name, static_cast<double>(step_nm) * 1e-6, range_name, text.c_str(), static_cast<double>(span_nm) * 1e-6,
                    one);
      throw std::invalid_argument(why);
    }
  };
  within(step, x, "--step", "--x", a.x, "point per line");
  within(step_y, y, a.step_y_mm > 0 ? "--step-y" : "--step", "--y", a.y, "line");
  request.step_x_nm = static_cast<uint32_t>(step);
  request.step_y_nm = static_cast<uint32_t>(step_y);
  request.pattern = a.pattern == "raster" ? digitizer_ScanPattern_PATTERN_RASTER
                                          : digitizer_ScanPattern_PATTERN_SERPENTINE;
  request.feed_um_s = static_cast<uint32_t>(a.feed_mm_s * 1000.0);
  if (a.mode == "fly") {
    // On the fly the device sets the feed that gives one reading every --step; --feed caps it.
    request.mode = digitizer_ScanMode_SCAN_MODE_FLY;
    if (!a.feed_given) request.feed_um_s = 0;
    request.plunger_follow_um_s = static_cast<uint32_t>(a.plunger_mm_s * 1000.0 + 0.5);
    if (a.pattern == "raster") throw std::invalid_argument("--mode fly runs serpentine: its two directions measure the gauge's latch delay");
    if (a.samples > 1 || a.settle_um > 0 || a.spread_um > 0 || a.median || a.approach_mm > 0 || a.reference_every > 0) {
      throw std::invalid_argument(
          "--mode fly takes one reading per point while the table moves: --samples, --settle-um, --spread-um, --median, "
          "--approach and --reference-every are for stop-and-go scans");
    }
  } else if (a.plunger_mm_s > 0) {
    throw std::invalid_argument("--plunger-mm-s is for --mode fly");
  }
  request.probe = digitizer_ProbeType_PROBE_DIGIMATIC;
  request.samples_per_point = a.samples;
  request.settle_ms = a.settle_ms;
  request.settle_tolerance_nm = static_cast<uint32_t>(a.settle_um * 1000.0 + 0.5);
  request.spread_tolerance_nm = static_cast<uint32_t>(a.spread_um * 1000.0 + 0.5);
  request.median = a.median;
  request.approach_nm = static_cast<uint32_t>(a.approach_mm * 1e6 + 0.5);
  request.reference_every_lines = a.reference_every;
  return request;
}

// Reads the scan's first point a.repeatability times before the scan and stores the result as the
// scan file's first record (in the hidden file until the device accepts the scan), so every point
// of the scan carries a standard uncertainty. A reading that fails stops the scan before it starts.
void measure_first_point(Session& session, const digitizer_Hello& device, const digitizer_ScanRequest& request,
                         const ScanArgs& a, ScanSink& file) {
  if (a.repeatability < 2) throw std::invalid_argument("--repeatability must be 0 (none) or 2..64 readings");
  move_table_to(session, request.x.min_nm, request.y.min_nm, device.axis_resolution_nm, request.feed_um_s, 120000);
  digitizer_Envelope record = digitizer_Envelope_init_zero;
  record.which_body = digitizer_Envelope_repeatability_tag;
  record.body.repeatability = measure_repeatability(session, a.repeatability);
  file.append(record);
  const digitizer_Repeatability& r = record.body.repeatability;
  if (!a.quiet) {
    std::printf("repeatability at the first point: s = %.4f mm over %u readings (range %.4f mm)\n", r.stddev_nm * 1e-6,
                r.count, (r.max_nm - r.min_nm) * 1e-6);
  }
}

std::string resume_hint(const ScanArgs& a) {
  char adaptive[96] = "";
  if (a.adaptive) std::snprintf(adaptive, sizeof adaptive, " --adaptive --tolerance %g", a.tolerance_mm);
  return "continue with: digitizer scan --resume" + std::string(adaptive) + " --device '" + a.device + "' -o " + a.output;
}

void print_adaptive(const AdaptiveResult& rounds, double tolerance_mm) {
  const RefinementPlan& last = rounds.last;
  if (!rounds.completed) {
    std::printf("adaptive: stopped in round %d after %zu new points\n", rounds.rounds, rounds.new_points);
    return;
  }
  std::printf("adaptive: %d rounds, %zu new points in %zu passes, a %zu x %zu grid\n", rounds.rounds, rounds.new_points,
              rounds.passes, last.columns, last.rows);
  if (last.noise_limited) {
    std::printf("adaptive: the readings' noise (sigma %.4f mm) alone makes a point miss its neighbours' prediction by up to "
                "%.4f mm, near or over the tolerance %.4f mm: more points cannot help (average --samples, filter, or give a "
                "larger tolerance)\n",
                last.noise_sigma_mm, last.noise_miss_mm, tolerance_mm);
  } else if (last.intervals_at_min > 0) {
    std::printf("adaptive: at the finest step (--min-step) points are still predicted worse than %.4f mm by their neighbours "
                "(worst %.4f mm at %.3f, %.3f)\n",
                tolerance_mm, last.worst_mm, last.worst_at.x, last.worst_at.y);
  } else {
    std::printf("adaptive: neighbours predict every point within %.4f mm (worst %.4f mm)\n", tolerance_mm, last.worst_mm);
  }
  if (rounds.fit_kept) {
    std::printf("adaptive: one B-spline surface keeps %.4f mm, validated between the samples (digitizer fit --tolerance %g "
                "--no-regions)\n",
                tolerance_mm, tolerance_mm);
  } else {
    std::printf("adaptive: one B-spline surface does not keep %.4f mm on these points: %s\n", tolerance_mm, rounds.fit_reason.c_str());
  }
}

}  // namespace

void print_summary(const ScanData& scan, const char* prefix) {
  // The points without the reference readings, which say how far the gauge drifted.
  ScanData data = scan;
  remove_drift(data, nullptr, "the scan", false);  // as measured: the extent below is of the raw readings
  std::optional<DriftRemoval> drift;
  try {
    ScanData corrected = scan;
    drift = remove_drift(corrected, nullptr, "the scan");
  } catch (const std::invalid_argument& error) {
    std::printf("%swarning: %s\n", prefix, error.what());
  }
  try {
    ScanData corrected = scan;
    if (const auto fly = correct_fly_scan(corrected, nullptr, "the scan", false)) std::printf("%s%s\n", prefix, fly_summary(*fly).c_str());
  } catch (const std::invalid_argument& error) {
    std::printf("%swarning: %s\n", prefix, error.what());
  }
  if (drift) {
    std::printf("%sdrift: the first point read again %zu times: up to %.4f mm, removed when the points are read "
                "(interpolation error bound %.4f mm)\n",
                prefix, drift->readings, drift->largest_mm, drift->interpolation_mm);
  }
  if (data.points.empty()) {
    std::printf("%s0 points\n", prefix);
    return;
  }
  int32_t lo[3] = {INT32_MAX, INT32_MAX, INT32_MAX}, hi[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
  for (const auto& p : data.points) {
    const int32_t v[3] = {p.x_nm, p.y_nm, p.z_nm};
    for (int i = 0; i < 3; ++i) {
      if (v[i] < lo[i]) lo[i] = v[i];
      if (v[i] > hi[i]) hi[i] = v[i];
    }
  }
  const uint32_t lines = data.points.back().line - data.points.front().line + 1;
  std::printf("%s%zu points in %" PRIu32 " lines\n", prefix, data.points.size(), lines);
  std::printf("%sextent x %.3f..%.3f  y %.3f..%.3f  z %.3f..%.3f mm\n", prefix, lo[0] * 1e-6,
              hi[0] * 1e-6, lo[1] * 1e-6, hi[1] * 1e-6, lo[2] * 1e-6, hi[2] * 1e-6);
  if (data.done) {
    std::printf("%sdevice time %.1f s%s\n", prefix, static_cast<double>(data.device_time_us) * 1e-6,
                data.passes.size() > 1 ? (" in " + std::to_string(data.passes.size()) + " passes").c_str() : "");
  }
  for (const auto& w : data.warnings) std::printf("%swarning: %s\n", prefix, w.c_str());
}

CLI::App* add_scan_command(CLI::App& app, ScanArgs& scan) {
  CLI::App* cmd = app.add_subcommand("scan", "scan a grid on the device and store it, or --resume a scan");
  cmd->add_option("--device", scan.device, "device URI: usb:, sim:part=dome, unix:PATH, tcp:HOST:PORT (else DIGITIZER_DEVICE or the config file)");
  cmd->add_option("--x", scan.x, "x range MIN:MAX in mm")->capture_default_str();
  cmd->add_option("--y", scan.y, "y range MIN:MAX in mm")->capture_default_str();
  cmd->add_option("--step", scan.step_mm, "grid step along a line, mm")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--step-y", scan.step_y_mm, "grid step between lines, mm (default: --step)")->check(CLI::PositiveNumber);
  cmd->add_option("--pattern", scan.pattern, "raster or serpentine")
      ->capture_default_str()->check(CLI::IsMember({"raster", "serpentine"}));
  cmd->add_option("--feed", scan.feed_mm_s, "table speed between points, mm/s (on the fly: the most the line's feed may be)")
      ->capture_default_str()->check(CLI::Range(0.01, 200.0))->each([&scan](const std::string&) { scan.feed_given = true; });
  cmd->add_option("--mode", scan.mode,
                  "stop: stop and read at every point; fly: each line at constant feed, readings back to back, one "
                  "every --step or closer (the feed follows the gauge's cycle)")
      ->capture_default_str()->check(CLI::IsMember({"stop", "fly"}));
  cmd->add_option("--plunger-mm-s", scan.plunger_mm_s,
                  "on the fly: the fastest the gauge's plunger falls after the part, mm/s; readings falling at 80 % of it "
                  "are flagged as lifted and left out of fits (default: the device's, 50)")
      ->check(CLI::Range(0.1, 10000.0));
  cmd->add_flag("--adaptive", scan.adaptive,
               "after the --step grid, measure new columns and rows where the part bends: an interval beside a point "
               "its neighbours predict worse than --tolerance gets one at its middle, round after round, down to --min-step");
  cmd->add_option("--tolerance", scan.tolerance_mm, "--adaptive: the error, mm, every point must be predicted within")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--min-step", scan.min_step_mm, "--adaptive: the finest step, mm (default --step / 8)")->check(CLI::PositiveNumber);
  cmd->add_option("--samples", scan.samples, "gauge readings averaged per point")->capture_default_str()->check(CLI::Range(1, 16));
  cmd->add_option("--settle-ms", scan.settle_ms, "wait after each move before reading")->capture_default_str()->check(CLI::Range(0, 10000));
  cmd->add_option("--settle-um", scan.settle_um, "then read until two readings agree within this, um (0: no)")->check(CLI::Range(0.0, 10000.0));
  cmd->add_option("--spread-um", scan.spread_um, "a point's samples must agree within this, um; else retaken once and flagged")->check(CLI::Range(0.0, 10000.0));
  cmd->add_flag("--median", scan.median, "the median of a point's samples instead of their mean");
  cmd->add_option("--approach", scan.approach_mm, "reach every point moving towards +x/+y: overshoot by this, mm (backlash)")
      ->check(CLI::Range(0.0, 10.0));
  cmd->add_option("--reference-every", scan.reference_every,
                  "read the scan's first point again after every N lines and after the last, and remove the gauge's "
                  "drift between those readings from every point (0: off)")
      ->check(CLI::Range(0, 100000));
  cmd->add_option("--repeatability", scan.repeatability,
                  "first read the scan's first point N times (2..64), moving 1 mm away and back each time, and store the "
                  "spread in the scan file: every point then carries a standard uncertainty (0: none)")
      ->check(CLI::Range(0, 64));
  cmd->add_option("--calibration", scan.calibration,
                  "the table calibration (digitizer calibrate) that corrects this scan's points: recorded in the scan "
                  "file with the raw points, which it must cover; none: no correction");
  cmd->add_option("-o,--output", scan.output, "scan file to write (with --resume: to continue)")->required();
  cmd->add_flag("--resume", scan.resume, "continue the scan in -o after Ctrl-C, a crash or a pulled cable; the grid comes from the file");
  cmd->add_flag("--force", scan.force, "replace an existing -o (once the device has accepted the new scan)")->excludes("--resume");
  cmd->add_option("--reconnect-s", scan.reconnect_s, "after a pulled cable, try this long to reach the device again (0: give up at once)")
      ->capture_default_str()->check(CLI::Range(0, 3600));
  cmd->add_option("--device-fit", scan.device_fit, "after the scan, pull the surface the device fitted while scanning into this SURF.json");
  cmd->add_option("--device-fit-model", scan.device_fit_model, "bezier (one bicubic patch) or bspline (5 x 5 cubic net)")
      ->capture_default_str()->check(CLI::IsMember({"bezier", "bspline"}));
  cmd->add_flag("-q,--quiet", scan.quiet, "print nothing but errors");
  return cmd;
}

CLI::App* add_pull_command(CLI::App& app, PullArgs& pull) {
  CLI::App* cmd = app.add_subcommand("pull", "fetch the surface the device fitted during its latest scan");
  cmd->add_option("--device", pull.device, "device URI: usb:, sim:part=dome, unix:PATH, tcp:HOST:PORT (else DIGITIZER_DEVICE or the config file)");
  cmd->add_option("--model", pull.model, "bezier (one bicubic patch) or bspline (5 x 5 cubic net)")
      ->capture_default_str()->check(CLI::IsMember({"bezier", "bspline"}));
  cmd->add_option("-o,--output", pull.output, "SURF.json to write")->required();
  cmd->add_option("--scan", pull.scan, "the scan's file: report the fit against its points, with its uncertainty");
  cmd->add_flag("-q,--quiet", pull.quiet, "print nothing but errors");
  return cmd;
}

int run_pull(const PullArgs& a) {
  auto transport = open_transport(a.device);
  Session session(*transport);
  const digitizer_Hello device = session.hello(5000, digitizer_Capability_CAP_DEVICE_FIT);
  write_device_fit(session, device, a.model, a.output, a.quiet, a.scan);
  return 0;
}

int run_scan(const ScanArgs& a) {
  std::optional<ScanData> stored;
  digitizer_ScanRequest request = digitizer_ScanRequest_init_zero;
  if (a.resume) {
    // As stored: an adaptive scan resumes its last pass, whose points are the file's last ones.
    stored = read_scan_file(a.output, ScanOrder::kAsStored);
    if (!stored->request) throw ScanFileError(a.output + ": has no scan request; there is nothing to resume");
    if (stored->done && !a.adaptive) {
      if (!a.quiet) std::printf("%s: the scan finished already (%zu points); nothing to resume\n", a.output.c_str(), stored->points.size());
      return 0;
    }
    request = *stored->request;
    if (stored->passes.size() > 1) {
      stored->points.erase(stored->points.begin(), stored->points.begin() + static_cast<std::ptrdiff_t>(stored->last_pass_first_point));
      // Only the last pass's points are the device's to resend; the earlier passes' LineDones are
      // not its lines (an adaptive file's lines are counted from its rows).
      stored->lines.clear();
    }
  } else {
    request = request_from(a);
    if (a.adaptive) {
      const std::string refusal = adaptive_refusal(request);
      if (!refusal.empty()) throw std::invalid_argument(refusal);
      if (!(a.tolerance_mm > 0)) throw std::invalid_argument("--adaptive needs --tolerance MM: the error every point must be predicted within");
      if (!a.device_fit.empty()) throw std::invalid_argument("--device-fit fits one pass on the device; an adaptive scan has many: fit on the host");
    }
    // A scan file is the only record of hours of table time: never replaced without asking, and
    // checked before the device moves.
    struct stat existing {};
    if (!a.force && ::stat(a.output.c_str(), &existing) == 0) {
      throw ScanFileError(a.output + ": exists already (" + std::to_string(existing.st_size) +
                          " bytes); give another name, --force to replace it, or --resume to continue the scan in it");
    }
  }
  // The calibration is checked before the table moves: a scan it does not cover could not be corrected.
  std::string calibration_json;
  std::string calibration_device;  // the device the calibration was measured on, checked once connected
  if (!a.resume && !a.calibration.empty() && a.calibration != "none") {
    const TableCalibration c = read_calibration_file(a.calibration, &calibration_json);
    calibration_device = c.device_id;
    const double x0 = request.x.min_nm * 1e-6, x1 = request.x.max_nm * 1e-6, y0 = request.y.min_nm * 1e-6, y1 = request.y.max_nm * 1e-6;
    if (!c.covers(x0, y0) || !c.covers(x1, y1)) {
      char text[200];
      std::snprintf(text, sizeof text, ": covers x %.3f..%.3f, y %.3f..%.3f mm; the scan asks x %.3f..%.3f, y %.3f..%.3f mm",
                    c.x0_mm, c.x1_mm(), c.y0_mm, c.y1_mm(), x0, x1, y0, y1);
      throw CalibrationError(a.calibration + text + "; calibrate over the whole area, or scan with --calibration none");
    }
  }
  uint32_t required = a.device_fit.empty() ? 0 : digitizer_Capability_CAP_DEVICE_FIT;
  if (a.resume) required |= digitizer_Capability_CAP_RESUME;

  const auto started = std::chrono::steady_clock::now();
  auto transport = open_transport(a.device);
  Session session(*transport);
  const digitizer_Hello device = session.hello(5000, required);
  if (!calibration_json.empty()) check_calibration_device(calibration_device, a.calibration, device.device_id);
  // The gauge the device has wired (its capabilities say which).
  if (!stored) {
    const bool caliper_only = (device.capabilities & digitizer_Capability_CAP_CALIPER_24BIT) != 0 &&
                              (device.capabilities & digitizer_Capability_CAP_DIGIMATIC) == 0;
    request.probe = caliper_only ? digitizer_ProbeType_PROBE_CALIPER_24BIT : digitizer_ProbeType_PROBE_DIGIMATIC;
  }
  // A device that does not know the mode would ignore it and stop at every point.
  if (flies(request) && (device.capabilities & digitizer_Capability_CAP_FLY_SCAN) == 0) {
    throw std::runtime_error(std::string("device ") + device.device_id + " cannot scan on the fly (its firmware is older): use --mode stop");
  }
  if (!a.quiet) {
    std::printf("device %s (%s, firmware %s), table %.0f x %.0f mm, gauge %u nm\n", device.device_id, device.board,
                device.firmware_version, device.table.x.max_nm * 1e-6, device.table.y.max_nm * 1e-6,
                device.gauge_resolution_nm);
    if (stored) std::printf("resuming %s after %zu points\n", a.output.c_str(), stored->points.size());
  }
  // A new scan's file appears only once the device has accepted the scan: a refused scan leaves
  // no file, and an existing one (with --force) stays until the new scan has started.
  ScanFileWriter file = stored ? ScanFileWriter::continue_file(a.output, stored->complete_bytes)
                               : ScanFileWriter::when_accepted(a.output, a.force);
  CaptureOptions options;
  // Acknowledge well before the device's ring is full (it pauses the scan when it is).
  if (device.point_ring_capacity > 0) options.ack_batch_points = std::max<uint32_t>(1, device.point_ring_capacity / 2);
  options.reconnect_timeout_ms = a.reconnect_s * 1000;
  // A bar with rate and ETA on a terminal; a plain line every tenth of the scan otherwise. On
  // standard error: standard output carries the results, for a pipe or a log to keep apart.
  ProgressPrinter progress(stderr, isatty(fileno(stderr)) != 0);
  const uint32_t stored_points = stored ? static_cast<uint32_t>(stored->points.size()) : 0;
  progress.start_at(stored_points);
  if (!a.quiet) {
    options.progress = [&progress](const CaptureProgress& p) { progress.update(p.points, p.points_total); };
  }
  options.notice = [](const std::string& text) { std::fprintf(stderr, "digitizer: %s\n", text.c_str()); };
  // Ctrl-C pauses the device's scan and stops after storing what is in flight.
  g_interrupted = 0;
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  options.stop_requested = [] { return g_interrupted != 0; };

  if (!calibration_json.empty()) file.append_calibration(calibration_json);
  if (!stored && a.repeatability > 0) measure_first_point(session, device, request, a, file);

  CaptureResult result;
  try {
    if (stored && stored->done) {
      result.done = *stored->done;  // an adaptive scan whose last pass ended: its rounds go on
      result.points = static_cast<uint32_t>(stored->points.size());
    } else {
      result = stored ? resume_capture(session, *stored, file, options)
                      : capture_scan(session, device, request, file, options);
    }
    if (a.adaptive && !result.interrupted && result.done.reason == digitizer_ScanEnd_SCAN_COMPLETED) {
      progress.finish();
      AdaptiveOptions adaptive;
      adaptive.tolerance_mm = a.tolerance_mm;
      adaptive.min_step_mm = a.min_step_mm;
      adaptive.quiet = a.quiet;
      const AdaptiveResult rounds = refine_scan(session, file, a.output, request, adaptive, options);
      if (!rounds.completed) result = rounds.failed;
      if (!a.quiet) print_adaptive(rounds, a.tolerance_mm);
    }
  } catch (const ScanRefused&) {
    throw;
  } catch (const TransportError& e) {
    throw TransportError(std::string(e.what()) + "\n" + resume_hint(a));
  } catch (const DeviceError& e) {
    throw DeviceError(std::string(e.what()) + "\n" + resume_hint(a));
  }
  progress.finish();
  signal(SIGINT, SIG_DFL);
  signal(SIGTERM, SIG_DFL);
  if (result.interrupted) {
    std::fprintf(stderr, "digitizer: stopped after %u points; the device has paused the scan and the points are in %s\n%s\n",
                 result.points, a.output.c_str(), resume_hint(a).c_str());
    return kExitInterrupted;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (!a.quiet) {
    const ScanData data = read_scan_file(a.output);
    print_summary(data, "");
    const double received = static_cast<double>(result.points - stored_points);
    std::printf("wall time %.2f s (%.0f points/s), %.1f wire bytes per point%s\n", seconds,
                received / (seconds > 0 ? seconds : 1e-9),
                received > 0 ? static_cast<double>(session.bytes_received()) / received : 0.0,
                result.reconnects ? (", " + std::to_string(result.reconnects) + " reconnects").c_str() : "");
    std::printf("wrote %s\n", a.output.c_str());
  }
  // The device's fit of whatever it measured, even of a scan cut short.
  if (!a.device_fit.empty()) write_device_fit(session, device, a.device_fit_model, a.device_fit, a.quiet, a.output);
  if (result.done.reason != digitizer_ScanEnd_SCAN_COMPLETED) {
    std::fprintf(stderr, "digitizer: scan %s after %u points%s%s; the points are in %s\n",
                 result.done.reason == digitizer_ScanEnd_SCAN_ABORTED ? "aborted" : "stopped by a fault", result.points,
                 result.faults ? ": " : "", result.last_fault_detail.c_str(), a.output.c_str());
    return 1;
  }
  return 0;
}

}  // namespace dg::host
