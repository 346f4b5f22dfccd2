// The calibration file and the bilinear correction of points by its map.
#include "host/scan/table_calibration.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <cmath>
#include <utility>

#include "host/io/whole_file.h"

namespace dg::host {

namespace {

constexpr double kLimitMm = 10000;        // the grid's origin and steps
constexpr double kLargestErrorMm = 10;    // a node's error or uncertainty

// Cell and weights of (x, y) for bilinear interpolation; requires covers().
struct Cell {
  size_t i, j;
  double fx, fy;
};

Cell cell_of(const TableCalibration& c, double x_mm, double y_mm) {
  const double u = (x_mm - c.x0_mm) / c.step_x_mm, v = (y_mm - c.y0_mm) / c.step_y_mm;
  // Clamped as doubles before the cast: a file's extreme grid can make u infinite or NaN.
  const double last_i = static_cast<double>(c.nx - 2), last_j = static_cast<double>(c.ny - 2);
  const size_t i = static_cast<size_t>(u >= 0 ? std::min(std::floor(u), last_i) : 0.0);
  const size_t j = static_cast<size_t>(v >= 0 ? std::min(std::floor(v), last_j) : 0.0);
  const double fx = u - static_cast<double>(i), fy = v - static_cast<double>(j);
  return {i, j, fx >= 0 ? std::min(fx, 1.0) : 0.0, fy >= 0 ? std::min(fy, 1.0) : 0.0};
}

}  // namespace

void TableCalibration::node_weights(double x_mm, double y_mm, size_t (&node)[4], double (&weight)[4]) const {
  const Cell k = cell_of(*this, x_mm, y_mm);
  const size_t a = k.j * nx + k.i;
  node[0] = a, node[1] = a + 1, node[2] = a + nx, node[3] = a + nx + 1;
  weight[0] = (1 - k.fx) * (1 - k.fy), weight[1] = k.fx * (1 - k.fy), weight[2] = (1 - k.fx) * k.fy, weight[3] = k.fx * k.fy;
}

namespace {

double bilinear(const TableCalibration& c, const std::vector<double>& values, double x_mm, double y_mm) {
  size_t node[4];
  double weight[4];
  c.node_weights(x_mm, y_mm, node, weight);
  return weight[0] * values[node[0]] + weight[1] * values[node[1]] + weight[2] * values[node[2]] + weight[3] * values[node[3]];
}

}  // namespace

bool TableCalibration::covers(double x_mm, double y_mm) const {
  // A micrometre of slack: scan positions are whole steps of the motors, the map's nodes too.
  const double slack = 1e-3;
  return nx >= 2 && ny >= 2 && x_mm >= x0_mm - slack && x_mm <= x1_mm() + slack && y_mm >= y0_mm - slack &&
         y_mm <= y1_mm() + slack;
}

double TableCalibration::z_error_at(double x_mm, double y_mm) const { return bilinear(*this, z_error_mm, x_mm, y_mm); }

double TableCalibration::u_at(double x_mm, double y_mm) const {
  // The nodes' uncertainties are not independent of their neighbours' (each is a local fit); the
  // interpolated u is bounded by the larger of the nodes', which is what is given.
  const Cell k = cell_of(*this, x_mm, y_mm);
  const size_t a = k.j * nx + k.i;
  return std::max(std::max(u_mm[a], u_mm[a + 1]), std::max(u_mm[a + nx], u_mm[a + nx + 1]));
}

std::string calibration_to_json(const TableCalibration& c) {
  nlohmann::ordered_json j;
  j["format"] = "digitizer table calibration";
  j["version"] = c.version();
  j["created_utc"] = c.created_utc;
  j["device_id"] = c.device_id;
  j["artefact"] = {{"kind", c.artefact}, {"flatness_mm", c.artefact_flatness_mm}};
  j["grid"] = {{"x0_mm", c.x0_mm}, {"y0_mm", c.y0_mm}, {"step_x_mm", c.step_x_mm}, {"step_y_mm", c.step_y_mm},
               {"nx", c.nx}, {"ny", c.ny}};
  j["z_error_mm"] = c.z_error_mm;
  j["u_mm"] = c.u_mm;
  if (c.has_axes) {
    j["axes"] = {{"artefact", "ball plate"},
                 {"created_utc", c.axes_created_utc},
                 {"scale_x_ppm", c.scale_x_ppm},
                 {"scale_y_ppm", c.scale_y_ppm},
                 {"squareness_urad", c.squareness_urad},
                 {"u_scale_x_ppm", c.u_scale_x_ppm},
                 {"u_scale_y_ppm", c.u_scale_y_ppm},
                 {"u_squareness_urad", c.u_squareness_urad},
                 {"balls", c.balls},
                 {"centre_rms_mm", c.ball_centre_rms_mm}};
    if (c.axes_with_lead) j["axes"]["lead_corrected"] = true;
    const Straightness& b = c.straightness;
    if (b.measured) {
      j["axes"]["straightness"] = {{"x_um", b.x_um},
                                   {"y_um", b.y_um},
                                   {"u_x_um", b.u_x_um},
                                   {"u_y_um", b.u_y_um},
                                   {"centre_x_mm", b.centre_x_mm},
                                   {"centre_y_mm", b.centre_y_mm},
                                   {"half_span_x_mm", b.half_span_x_mm},
                                   {"half_span_y_mm", b.half_span_y_mm}};
    }
  }
  if (c.has_gauge_tilt) {
    j["gauge"] = {{"artefact", "reference sphere"},
                  {"created_utc", c.gauge_created_utc},
                  {"diameter_mm", c.sphere_diameter_mm},
                  {"tilt_x_urad", c.gauge_tilt_x_urad},
                  {"tilt_y_urad", c.gauge_tilt_y_urad},
                  {"u_tilt_x_urad", c.u_gauge_tilt_x_urad},
                  {"u_tilt_y_urad", c.u_gauge_tilt_y_urad},
                  {"points", c.sphere_points},
                  {"residual_rms_mm", c.sphere_rms_mm}};
  }
  if (c.lead.measured) {
    const LeadError& e = c.lead;
    j["lead_screws"] = {{"artefact", "reference sphere"}, {"lead_mm", e.lead_mm},     {"x_sin_um", e.x_sin_um},
                        {"x_cos_um", e.x_cos_um},         {"y_sin_um", e.y_sin_um}, {"y_cos_um", e.y_cos_um},
                        {"u_x_um", e.u_x_um},             {"u_y_um", e.u_y_um}};
  }
  if (c.has_gauge_scale) {
    j["gauge_scale"] = {{"artefact", "step gauge"},
                        {"created_utc", c.scale_created_utc},
                        {"scale_ppm", c.gauge_scale_ppm},
                        {"u_scale_ppm", c.u_gauge_scale_ppm},
                        {"steps", c.scale_steps},
                        {"residual_rms_mm", c.scale_rms_mm}};
  }
  j["fit"] = {{"points", c.points},
              {"noise_mm", c.noise_mm},
              {"plane_removed_mm", {c.plane_mm[0], c.plane_mm[1], c.plane_mm[2]}},
              {"residual_rms_mm", c.residual_rms_mm}};
  return j.dump(1) + "\n";
}

TableCalibration calibration_from_json(const std::string& text, const std::string& name) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw CalibrationError(name + ": not a JSON object (is this a calibration file?)");
  auto need = [&](const nlohmann::json& object, const char* key, const std::string& where) -> const nlohmann::json& {
    if (!object.is_object() || !object.contains(key)) throw CalibrationError(name + ": " + where + key + " is missing");
    return object.at(key);
  };
  auto number = [&](const nlohmann::json& object, const char* key, const std::string& where) {
    const nlohmann::json& v = need(object, key, where);
    if (!v.is_number() || !std::isfinite(v.get<double>())) throw CalibrationError(name + ": " + where + key + " is not a finite number");
    return v.get<double>();
  };
  if (!j.contains("format") || j["format"] != "digitizer table calibration") {
    throw CalibrationError(name + ": not a digitizer table calibration (\"format\" is missing or different)");
  }
  const double version = number(j, "version", "");
  if (version != TableCalibration::kVersion && version != TableCalibration::kVersionWithTilt &&
      version != TableCalibration::kVersionWithoutTilt) {
    char words[96];  // %g: the file's number may be anything finite
    std::snprintf(words, sizeof words, ": calibration version %g; this digitizer reads versions %d to %d", version,
                  TableCalibration::kVersionWithoutTilt, TableCalibration::kVersion);
    throw CalibrationError(name + words);
  }
  TableCalibration c;
  if (j.contains("created_utc") && j["created_utc"].is_string()) c.created_utc = j["created_utc"].get<std::string>();
  if (j.contains("device_id") && j["device_id"].is_string()) c.device_id = j["device_id"].get<std::string>();
  const nlohmann::json& artefact = need(j, "artefact", "");
  if (artefact.contains("kind") && artefact["kind"].is_string()) c.artefact = artefact["kind"].get<std::string>();
  c.artefact_flatness_mm = number(artefact, "flatness_mm", "artefact.");
  const nlohmann::json& grid = need(j, "grid", "");
  c.x0_mm = number(grid, "x0_mm", "grid."), c.y0_mm = number(grid, "y0_mm", "grid.");
  c.step_x_mm = number(grid, "step_x_mm", "grid."), c.step_y_mm = number(grid, "step_y_mm", "grid.");
  const double nx = number(grid, "nx", "grid."), ny = number(grid, "ny", "grid.");
  if (!(c.step_x_mm > 0 && c.step_y_mm > 0)) throw CalibrationError(name + ": grid steps must be positive");
  // A table is not ten metres long, nor out by ten millimetres: beyond that the file is not a
  // calibration, and its numbers would overflow a scan's nanometres.
  if (std::fabs(c.x0_mm) > kLimitMm || std::fabs(c.y0_mm) > kLimitMm || c.step_x_mm > kLimitMm || c.step_y_mm > kLimitMm) {
    throw CalibrationError(name + ": the grid lies beyond 10 m");
  }
  if (nx < 2 || ny < 2 || nx > 10000 || ny > 10000 || nx != std::floor(nx) || ny != std::floor(ny)) {
    throw CalibrationError(name + ": the grid needs 2 to 10000 whole nodes each way");
  }
  c.nx = static_cast<size_t>(nx), c.ny = static_cast<size_t>(ny);
  for (const bool is_u : {false, true}) {
    const char* key = is_u ? "u_mm" : "z_error_mm";
    const nlohmann::json& values = need(j, key, "");
    if (!values.is_array() || values.size() != c.nx * c.ny) {
      throw CalibrationError(name + ": " + key + " must hold nx * ny = " + std::to_string(c.nx * c.ny) + " numbers");
    }
    std::vector<double>& out = is_u ? c.u_mm : c.z_error_mm;
    for (size_t k = 0; k < values.size(); ++k) {
      if (!values[k].is_number() || !std::isfinite(values[k].get<double>()) || (is_u && values[k].get<double>() < 0) ||
          std::fabs(values[k].get<double>()) > kLargestErrorMm) {
        throw CalibrationError(name + ": " + key + "[" + std::to_string(k) + "] is not a finite number" + (is_u ? " >= 0" : "") +
                               " within 10 mm");
      }
      out.push_back(values[k].get<double>());
    }
  }
  if (j.contains("axes")) {
    const nlohmann::json& axes = j["axes"];
    c.has_axes = true;
    c.scale_x_ppm = number(axes, "scale_x_ppm", "axes."), c.scale_y_ppm = number(axes, "scale_y_ppm", "axes.");
    c.squareness_urad = number(axes, "squareness_urad", "axes.");
    c.u_scale_x_ppm = number(axes, "u_scale_x_ppm", "axes."), c.u_scale_y_ppm = number(axes, "u_scale_y_ppm", "axes.");
    c.u_squareness_urad = number(axes, "u_squareness_urad", "axes.");
    // A table off by more than 2 % or 20 mrad is broken, not calibrated.
    if (std::fabs(c.scale_x_ppm) > 20000 || std::fabs(c.scale_y_ppm) > 20000 || std::fabs(c.squareness_urad) > 20000) {
      throw CalibrationError(name + ": axes: scale beyond 20000 ppm or squareness beyond 20000 urad");
    }
    if (axes.contains("created_utc") && axes["created_utc"].is_string()) c.axes_created_utc = axes["created_utc"].get<std::string>();
    if (axes.contains("balls") && axes["balls"].is_number_unsigned()) c.balls = axes["balls"].get<size_t>();
    if (axes.contains("centre_rms_mm") && axes["centre_rms_mm"].is_number()) c.ball_centre_rms_mm = axes["centre_rms_mm"].get<double>();
    c.axes_with_lead = axes.contains("lead_corrected") && axes["lead_corrected"] == true;
    if (axes.contains("straightness")) {
      if (version < TableCalibration::kVersion) {
        throw CalibrationError(name + ": the ways' straightness in a version " + std::to_string(static_cast<int>(version)) +
                               " file (it came with version 3): the file was edited or is damaged");
      }
      const nlohmann::json& bow = axes["straightness"];
      Straightness& b = c.straightness;
      b.measured = true;
      b.x_um = number(bow, "x_um", "axes.straightness."), b.y_um = number(bow, "y_um", "axes.straightness.");
      b.u_x_um = number(bow, "u_x_um", "axes.straightness."), b.u_y_um = number(bow, "u_y_um", "axes.straightness.");
      b.centre_x_mm = number(bow, "centre_x_mm", "axes.straightness."), b.centre_y_mm = number(bow, "centre_y_mm", "axes.straightness.");
      b.half_span_x_mm = number(bow, "half_span_x_mm", "axes.straightness.");
      b.half_span_y_mm = number(bow, "half_span_y_mm", "axes.straightness.");
      // A way bent by a millimetre is broken; a span under a millimetre measured no bow.
      if (std::fabs(b.x_um) > 1000 || std::fabs(b.y_um) > 1000 || b.u_x_um < 0 || b.u_y_um < 0 || !(b.half_span_x_mm >= 1) ||
          !(b.half_span_y_mm >= 1) || b.half_span_x_mm > kLimitMm || b.half_span_y_mm > kLimitMm ||
          std::fabs(b.centre_x_mm) > kLimitMm || std::fabs(b.centre_y_mm) > kLimitMm) {
        throw CalibrationError(name + ": axes.straightness: a bow beyond 1000 um, a negative uncertainty, or a span not "
                               "between 1 mm and 10 m");
      }
    }
  }
  if (j.contains("gauge")) {
    if (version == TableCalibration::kVersionWithoutTilt) {
      throw CalibrationError(name + ": a gauge tilt in a version 1 file (the tilt came with version 2): the file was edited or is damaged");
    }
    const nlohmann::json& gauge = j["gauge"];
    c.has_gauge_tilt = true;
    c.gauge_tilt_x_urad = number(gauge, "tilt_x_urad", "gauge."), c.gauge_tilt_y_urad = number(gauge, "tilt_y_urad", "gauge.");
    c.u_gauge_tilt_x_urad = number(gauge, "u_tilt_x_urad", "gauge."), c.u_gauge_tilt_y_urad = number(gauge, "u_tilt_y_urad", "gauge.");
    c.sphere_diameter_mm = number(gauge, "diameter_mm", "gauge.");
    // What calibrate_gauge_tilt accepts: beyond 50 mrad the plunger binds.
    if (std::hypot(c.gauge_tilt_x_urad, c.gauge_tilt_y_urad) > 50000 || c.u_gauge_tilt_x_urad < 0 || c.u_gauge_tilt_y_urad < 0) {
      throw CalibrationError(name + ": gauge: a tilt beyond 50000 urad or a negative uncertainty");
    }
    if (gauge.contains("created_utc") && gauge["created_utc"].is_string()) c.gauge_created_utc = gauge["created_utc"].get<std::string>();
    if (gauge.contains("points") && gauge["points"].is_number_unsigned()) c.sphere_points = gauge["points"].get<size_t>();
    if (gauge.contains("residual_rms_mm") && gauge["residual_rms_mm"].is_number()) c.sphere_rms_mm = gauge["residual_rms_mm"].get<double>();
  }
  if (j.contains("lead_screws")) {
    if (version < TableCalibration::kVersion) {
      throw CalibrationError(name + ": the screws' periodic error in a version " + std::to_string(static_cast<int>(version)) +
                             " file (it came with version 3): the file was edited or is damaged");
    }
    const nlohmann::json& lead = j["lead_screws"];
    LeadError& e = c.lead;
    e.measured = true;
    e.lead_mm = number(lead, "lead_mm", "lead_screws.");
    e.x_sin_um = number(lead, "x_sin_um", "lead_screws."), e.x_cos_um = number(lead, "x_cos_um", "lead_screws.");
    e.y_sin_um = number(lead, "y_sin_um", "lead_screws."), e.y_cos_um = number(lead, "y_cos_um", "lead_screws.");
    e.u_x_um = number(lead, "u_x_um", "lead_screws."), e.u_y_um = number(lead, "u_y_um", "lead_screws.");
    // What calibrate_gauge_tilt accepts, and a screw wobbling by a millimetre is broken.
    if (!(e.lead_mm >= 0.5 && e.lead_mm <= 100) || std::fabs(e.x_sin_um) > 1000 || std::fabs(e.x_cos_um) > 1000 ||
        std::fabs(e.y_sin_um) > 1000 || std::fabs(e.y_cos_um) > 1000 || e.u_x_um < 0 || e.u_y_um < 0) {
      throw CalibrationError(name + ": lead_screws: a lead outside 0.5..100 mm, a term beyond 1000 um or a negative uncertainty");
    }
  }
  if (j.contains("gauge_scale")) {
    if (version == TableCalibration::kVersionWithoutTilt) {
      throw CalibrationError(name + ": a gauge scale in a version 1 file (the scale came with version 2): the file was edited or is damaged");
    }
    const nlohmann::json& scale = j["gauge_scale"];
    c.has_gauge_scale = true;
    c.gauge_scale_ppm = number(scale, "scale_ppm", "gauge_scale."), c.u_gauge_scale_ppm = number(scale, "u_scale_ppm", "gauge_scale.");
    // What calibrate_gauge_scale accepts: a gauge 2 % off is broken.
    if (std::fabs(c.gauge_scale_ppm) > 20000 || c.u_gauge_scale_ppm < 0) {
      throw CalibrationError(name + ": gauge_scale: a scale beyond 20000 ppm or a negative uncertainty");
    }
    if (scale.contains("created_utc") && scale["created_utc"].is_string()) c.scale_created_utc = scale["created_utc"].get<std::string>();
    if (scale.contains("steps") && scale["steps"].is_number_unsigned()) c.scale_steps = scale["steps"].get<size_t>();
    if (scale.contains("residual_rms_mm") && scale["residual_rms_mm"].is_number()) c.scale_rms_mm = scale["residual_rms_mm"].get<double>();
  }
  if (j.contains("fit") && j["fit"].is_object()) {
    const nlohmann::json& fit = j["fit"];
    if (fit.contains("noise_mm") && fit["noise_mm"].is_number()) c.noise_mm = fit["noise_mm"].get<double>();
    if (fit.contains("residual_rms_mm") && fit["residual_rms_mm"].is_number()) c.residual_rms_mm = fit["residual_rms_mm"].get<double>();
    if (fit.contains("points") && fit["points"].is_number_unsigned()) c.points = fit["points"].get<size_t>();
    if (fit.contains("plane_removed_mm") && fit["plane_removed_mm"].is_array() && fit["plane_removed_mm"].size() == 3) {
      for (size_t k = 0; k < 3; ++k) {
        if (fit["plane_removed_mm"][k].is_number()) c.plane_mm[k] = fit["plane_removed_mm"][k].get<double>();
      }
    }
  }
  return c;
}

void check_calibration_device(const std::string& measured_on, const std::string& path, const std::string& device_id) {
  if (measured_on.empty() || device_id.empty() || measured_on == device_id) return;
  throw CalibrationError(path + ": measured on device " + measured_on + ", and these points come from device " + device_id +
                         ": a table's errors are its own; calibrate this device, or use --calibration none");
}

TableCalibration read_calibration_file(const std::string& path, std::string* text) {
  std::string bytes;
  if (!read_whole_file(path, &bytes)) throw CalibrationError(path + ": cannot open: " + std::strerror(errno));
  TableCalibration c = calibration_from_json(bytes, path);
  if (text != nullptr) *text = std::move(bytes);
  return c;
}

void apply_calibration(const TableCalibration& c, PointCloud& cloud, const std::string& name) {
  for (size_t k = 0; k < cloud.points.size(); ++k) {
    const Point3& p = cloud.points[k];
    if (!c.covers(p.x, p.y)) {
      char where[160];
      std::snprintf(where, sizeof where, "point %zu at (%.3f, %.3f) mm lies outside the calibrated travel x %.3f..%.3f, y %.3f..%.3f mm",
                    k + 1, p.x, p.y, c.x0_mm, c.x1_mm(), c.y0_mm, c.y1_mm());
      throw CalibrationError(name + ": " + where + "; calibrate over the whole scanned area");
    }
  }
  for (size_t k = 0; k < cloud.points.size(); ++k) {
    Point3& p = cloud.points[k];
    if (cloud.sigma) {
      const double u = c.u_at(p.x, p.y);
      (*cloud.sigma)[k] = std::hypot((*cloud.sigma)[k], u);
    }
    p.z -= c.z_error_at(p.x, p.y);
    const double commanded_x = p.x, commanded_y = p.y;  // the screws turn with the command
    if (c.has_axes) {
      const double q = c.squareness_urad * 1e-6;
      const double x = p.x * (1 + c.scale_x_ppm * 1e-6) + p.y * std::sin(q) + c.straightness.dx_mm(p.y);
      p.y = p.y * (1 + c.scale_y_ppm * 1e-6) * std::cos(q) + c.straightness.dy_mm(p.x);
      p.x = x;
    }
    p.x += c.lead.dx_mm(commanded_x);
    p.y += c.lead.dy_mm(commanded_y);
    if (c.has_gauge_tilt) {
      // The reading's own height shears it: measured from the gauge's zero, as the tilt was fitted.
      const double sx = std::sin(c.gauge_tilt_x_urad * 1e-6), sy = std::sin(c.gauge_tilt_y_urad * 1e-6);
      p.x += p.z * sx, p.y += p.z * sy;
      p.z *= std::sqrt(1 - sx * sx - sy * sy);
    }
    if (c.has_gauge_scale) {
      p.z /= 1 + c.gauge_scale_ppm * 1e-6;
      if (cloud.sigma) (*cloud.sigma)[k] = std::hypot((*cloud.sigma)[k], p.z * c.u_gauge_scale_ppm * 1e-6);
    }
  }
}

std::optional<TableCalibration> correct_by_record(ScanData& scan, std::vector<double>* sigma_mm, const std::string& name) {
  if (!scan.calibration_json) return std::nullopt;
  const TableCalibration c = calibration_from_json(*scan.calibration_json, name + " (its calibration record)");
  PointCloud cloud;
  for (const PointSample& p : scan.points) cloud.points.push_back({p.x_nm * 1e-6, p.y_nm * 1e-6, p.z_nm * 1e-6});
  if (sigma_mm != nullptr && sigma_mm->size() == scan.points.size()) cloud.sigma = *sigma_mm;
  apply_calibration(c, cloud, name);
  for (size_t k = 0; k < scan.points.size(); ++k) {
    scan.points[k].x_nm = static_cast<int32_t>(std::lround(cloud.points[k].x * 1e6));
    scan.points[k].y_nm = static_cast<int32_t>(std::lround(cloud.points[k].y * 1e6));
    scan.points[k].z_nm = static_cast<int32_t>(std::lround(cloud.points[k].z * 1e6));
  }
  if (cloud.sigma) *sigma_mm = *cloud.sigma;
  return c;
}

}  // namespace dg::host
