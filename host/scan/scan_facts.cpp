// A scan's record put into words: the request's settings and what the device reported.
#include "host/scan/scan_facts.h"

#include <cstdio>
#include <stdexcept>

#include "common/proto/scan_grid.h"
#include "host/scan/drift_removal.h"
#include "host/scan/fly_correction.h"
#include "host/scan/table_calibration.h"

namespace dg::host {

std::string reading_settings(const digitizer_ScanRequest& r) {
  char part[128];
  std::string out;
  if (flies(r)) {
    std::snprintf(part, sizeof part, "on the fly: one reading per point while the table moves, the feed from the gauge's cycle");
    out += part;
    if (r.feed_um_s) {
      std::snprintf(part, sizeof part, " (at most %.2f mm/s)", r.feed_um_s * 1e-3);
      out += part;
    }
    std::snprintf(part, sizeof part, ", plunger %.1f mm/s", (r.plunger_follow_um_s ? r.plunger_follow_um_s : kDefaultPlungerFollowUmS) * 1e-3);
    return out + part;
  }
  if (r.feed_um_s) {
    std::snprintf(part, sizeof part, "feed %.2f mm/s, ", r.feed_um_s * 1e-3);
    out += part;
  } else {
    out += "feed the device's default, ";
  }
  std::snprintf(part, sizeof part, "%u sample%s per point (%s), settle %u ms", r.samples_per_point > 1 ? r.samples_per_point : 1,
                r.samples_per_point > 1 ? "s" : "", r.median ? "median" : "mean", r.settle_ms);
  out += part;
  if (r.settle_tolerance_nm) {
    std::snprintf(part, sizeof part, " until two readings agree within %.1f um", r.settle_tolerance_nm * 1e-3);
    out += part;
  }
  if (r.spread_tolerance_nm) {
    std::snprintf(part, sizeof part, ", spread within %.1f um", r.spread_tolerance_nm * 1e-3);
    out += part;
  }
  if (r.approach_nm) {
    std::snprintf(part, sizeof part, ", approach %.3f mm", r.approach_nm * 1e-6);
    out += part;
  }
  if (r.reference_every_lines) {
    std::snprintf(part, sizeof part, ", the first point read again after every %u line%s", static_cast<unsigned>(r.reference_every_lines),
                  r.reference_every_lines > 1 ? "s" : "");
    out += part;
  }
  return out;
}

std::vector<std::string> scan_facts(const ScanData& data) {
  std::vector<std::string> facts;
  char line[200];
  if (data.device) {
    std::snprintf(line, sizeof line, "device %s (%s, firmware %s), gauge resolution %u nm", data.device->device_id,
                  data.device->board, data.device->firmware_version, static_cast<unsigned>(data.device->gauge_resolution_nm));
    facts.push_back(line);
  }
  if (data.request) {
    const digitizer_ScanRequest& r = *data.request;
    std::snprintf(line, sizeof line, "grid x %.3f..%.3f mm, y %.3f..%.3f mm, steps %.3f x %.3f mm, %s", r.x.min_nm * 1e-6,
                  r.x.max_nm * 1e-6, r.y.min_nm * 1e-6, r.y.max_nm * 1e-6, r.step_x_nm * 1e-6, r.step_y_nm * 1e-6,
                  r.pattern == digitizer_ScanPattern_PATTERN_RASTER ? "raster" : "serpentine");
    facts.push_back(line);
    facts.push_back("read with " + reading_settings(r));
  }
  if (data.repeatability) {
    const digitizer_Repeatability& q = *data.repeatability;
    std::snprintf(line, sizeof line, "repeatability before the scan: s = %.2f um over %u readings at (%.3f, %.3f) mm",
                  q.stddev_nm * 1e-3, static_cast<unsigned>(q.count), q.x_nm * 1e-6, q.y_nm * 1e-6);
    facts.push_back(line);
  } else {
    facts.push_back("repeatability: not measured before the scan (scan --repeatability N)");
  }
  // On the fly: the latch delay the lines measured and the readings taken in the air.
  if (data.request && flies(*data.request)) {
    try {
      ScanData corrected = data;
      if (const auto fly = correct_fly_scan(corrected, nullptr, "the scan", false)) facts.push_back("scanned " + fly_summary(*fly));
    } catch (const std::invalid_argument& error) {
      facts.push_back(std::string("scanned on the fly: ") + error.what());
    }
  }
  // Say which calibration corrected the points, or that none did, rather than leave a reader to
  // assume one was. A flat's calibration corrects the travel's height error only.
  if (data.calibration_json) {
    try {
      const TableCalibration c = calibration_from_json(*data.calibration_json, "the scan's calibration record");
      char text[400];
      std::snprintf(text, sizeof text,
                    "calibration: the table's travel height error, measured on a %s (flatness %.4f mm) on %s%s%s, over "
                    "x %.3f..%.3f, y %.3f..%.3f mm",
                    c.artefact.c_str(), c.artefact_flatness_mm, c.created_utc.empty() ? "an unknown date" : c.created_utc.c_str(),
                    c.device_id.empty() ? "" : " with ", c.device_id.c_str(), c.x0_mm, c.x1_mm(), c.y0_mm, c.y1_mm());
      std::string fact = text;
      if (c.has_axes) {
        std::snprintf(text, sizeof text,
                      "; the axes from a ball plate (%zu balls): scale x %+.1f ppm (u %.1f), y %+.1f ppm (u %.1f), "
                      "squareness %+.1f urad (u %.1f)",
                      c.balls, c.scale_x_ppm, c.u_scale_x_ppm, c.scale_y_ppm, c.u_scale_y_ppm, c.squareness_urad, c.u_squareness_urad);
        fact += text;
        if (c.straightness.measured) {
          std::snprintf(text, sizeof text, ", straightness (bows) %+.2f um in x (u %.2f) and %+.2f um in y (u %.2f)",
                        c.straightness.x_um, c.straightness.u_x_um, c.straightness.y_um, c.straightness.u_y_um);
          fact += text;
        }
      } else {
        fact += "; squareness and scale not compensated";
      }
      if (c.lead.measured) {
        std::snprintf(text, sizeof text, "; the lead screws' periodic error (%.2f mm a turn): %.2f um in x (u %.2f), %.2f um in y (u %.2f)",
                      c.lead.lead_mm, c.lead.amplitude_x_um(), c.lead.u_x_um, c.lead.amplitude_y_um(), c.lead.u_y_um);
        fact += text;
      }
      facts.push_back(fact);
    } catch (const CalibrationError& error) {
      facts.push_back(std::string("calibration: a record that cannot be used: ") + error.what());
    }
  } else {
    facts.push_back("calibration: none; the points are the table's nominal positions and the gauge's readings, with no "
                    "machine errors (travel flatness, squareness, scale) compensated");
  }
  // The drift the reference readings measured, and the points without them.
  ScanData points_only = data;
  try {
    const std::optional<DriftRemoval> drift = remove_drift(points_only, nullptr, "the scan");
    if (drift) {
      std::snprintf(line, sizeof line,
                    "drift: the first point read again %zu times: up to %.4f mm, removed by interpolation in time "
                    "(its error bound %.4f mm)",
                    drift->readings, drift->largest_mm, drift->interpolation_mm);
    } else {
      std::snprintf(line, sizeof line, "drift: not measured (scan --reference-every N reads the first point again)");
    }
    facts.push_back(line);
  } catch (const std::invalid_argument& error) {
    facts.push_back(std::string("drift: reference readings that cannot be used: ") + error.what());
  }
  // An adaptive scan's lines are its rows (each pass added runs to them).
  std::snprintf(line, sizeof line, "%zu points in %zu lines", points_only.points.size(),
                data.passes.size() > 1 && !data.points.empty() ? static_cast<size_t>(data.points.back().line) + 1 : data.lines.size());
  facts.push_back(line);
  if (data.done) {
    std::snprintf(line, sizeof line, "scan %s in %.1f s of device time%s",
                  data.done->reason == digitizer_ScanEnd_SCAN_COMPLETED ? "completed" : "cut short",
                  static_cast<double>(data.device_time_us) * 1e-6,
                  data.passes.size() > 1 ? (" in " + std::to_string(data.passes.size()) + " passes (an adaptive scan)").c_str() : "");
    facts.push_back(line);
  }
  return facts;
}

}  // namespace dg::host
