// A table's calibration: the height error of its XY travel on a grid, measured on a flat, its
// file (JSON), and the correction of scan points by it.
#pragma once
#include <cmath>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/scan/point_reader.h"
#include "host/scan/scan_sink.h"

namespace dg::host {

// A calibration file that cannot be read or used; the message names the file and what is wrong.
class CalibrationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The ways' straightness from a ball plate of at least three rows and three columns: the y axis's
// path bows in x and the x axis's in y, each a parabola through the plate's span. Each figure is the
// sagitta over the outer balls' span in micrometres (positive: the path's middle lies towards +x,
// or +y, of the chord through its ends); the linear part of a bent way is the squareness and scale.
struct Straightness {
  bool measured = false;
  double x_um = 0, y_um = 0, u_x_um = 0, u_y_um = 0;
  double centre_x_mm = 0, centre_y_mm = 0, half_span_x_mm = 0, half_span_y_mm = 0;
  // What the bow adds to the table's x at commanded y, and to its y at commanded x (mm). Like the
  // scale and squareness, it is nothing at the commanded origin: the table stands where homing put
  // it there, and the plate's placement takes the bow's offset at its middle.
  double dx_mm(double y_mm) const { return bow(x_um, y_mm, centre_y_mm, half_span_y_mm); }
  double dy_mm(double x_mm) const { return bow(y_um, x_mm, centre_x_mm, half_span_x_mm); }
  // Their standard uncertainties there (mm).
  double u_dx_mm(double y_mm) const { return std::fabs(bow(u_x_um, y_mm, centre_y_mm, half_span_y_mm)); }
  double u_dy_mm(double x_mm) const { return std::fabs(bow(u_y_um, x_mm, centre_x_mm, half_span_x_mm)); }

 private:
  static double bow(double sagitta_um, double at_mm, double centre_mm, double half_span_mm) {
    if (!(half_span_mm > 0)) return 0;
    return -sagitta_um * 1e-3 * ((at_mm - centre_mm) * (at_mm - centre_mm) - centre_mm * centre_mm) / (half_span_mm * half_span_mm);
  }
};

// The lead screws' periodic error, once a turn, from a reference sphere's flanks: the table stands
// e_x = x_sin sin(2 pi x / lead) + x_cos (cos(2 pi x / lead) - 1) ahead of its command in x, and
// e_y the same in y; nothing at the commanded origin, where homing leaves the screws.
struct LeadError {
  bool measured = false;
  double lead_mm = 0;
  double x_sin_um = 0, x_cos_um = 0, y_sin_um = 0, y_cos_um = 0;
  double u_x_um = 0, u_y_um = 0;  // each term's standard uncertainty (the larger of the pair's)
  double dx_mm(double x_mm) const { return term(x_sin_um, x_cos_um, x_mm); }
  double dy_mm(double y_mm) const { return term(y_sin_um, y_cos_um, y_mm); }
  double amplitude_x_um() const { return std::hypot(x_sin_um, x_cos_um); }
  double amplitude_y_um() const { return std::hypot(y_sin_um, y_cos_um); }
  // The standard uncertainty of dx_mm and dy_mm there (mm): each term's u by its own factor.
  double u_dx_mm(double x_mm) const { return u_term(u_x_um, x_mm); }
  double u_dy_mm(double y_mm) const { return u_term(u_y_um, y_mm); }

 private:
  double term(double sin_um, double cos_um, double t_mm) const {
    if (!measured || !(lead_mm > 0)) return 0;
    const double turn = 2 * 3.14159265358979323846 * t_mm / lead_mm;
    return 1e-3 * (sin_um * std::sin(turn) + cos_um * (std::cos(turn) - 1));
  }
  double u_term(double u_um, double t_mm) const {
    if (!measured || !(lead_mm > 0)) return 0;
    const double turn = 2 * 3.14159265358979323846 * t_mm / lead_mm;
    return 1e-3 * u_um * std::hypot(std::sin(turn), std::cos(turn) - 1);
  }
};

struct TableCalibration {
  // Version 2 adds the gauge's tilt and scale, version 3 the ways' straightness and the screws'
  // periodic error; a file is written with the lowest version that holds what it has, which readers
  // that know no later part still read correctly. An older reader refuses a later version rather
  // than ignore a correction.
  static constexpr int kVersion = 3;
  static constexpr int kVersionWithTilt = 2;
  static constexpr int kVersionWithoutTilt = 1;
  std::string created_utc;  // ISO 8601, when it was measured
  std::string device_id;    // the device it was measured on ("" when the scan did not say)
  std::string artefact = "flat";
  double artefact_flatness_mm = 0;  // the flat's certified flatness (peak to valley)
  // The map's nodes: x0 + i step_x, y0 + j step_y, i < nx, j < ny, row by row (j nx + i).
  double x0_mm = 0, y0_mm = 0, step_x_mm = 1, step_y_mm = 1;
  size_t nx = 0, ny = 0;
  std::vector<double> z_error_mm;  // what the travel adds to a reading at each node
  std::vector<double> u_mm;        // each node's standard uncertainty (k = 1)
  double noise_mm = 0;             // the gauge noise seen on the flat
  double plane_mm[3] = {};         // a + b x + c y taken out: the flat's own setup, not the machine
  double residual_rms_mm = 0;      // RMS of the flat's readings after the plane and the map
  size_t points = 0;               // readings the map was made of
  // The axes' errors from a ball plate (ball_plate_calibration.h), when measured: a point's (x, y)
  // is corrected to where the table really was, x' = x (1 + scale_x) + y sin(q), y' = y (1 +
  // scale_y) cos(q); the map stays indexed by the commanded position.
  bool has_axes = false;
  double scale_x_ppm = 0, scale_y_ppm = 0, squareness_urad = 0;
  double u_scale_x_ppm = 0, u_scale_y_ppm = 0, u_squareness_urad = 0;
  Straightness straightness;  // within the axes: x' and y' gain straightness.dx_mm(y), dy_mm(x)
  size_t balls = 0;
  double ball_centre_rms_mm = 0;
  bool axes_with_lead = false;  // the plate's readings were corrected by the screws' periodic error
  std::string axes_created_utc;
  // The gauge's tilt from a reference sphere (gauge_tilt_calibration.h), when measured: after the
  // map and the axes, a point read z high moves to (x + z sin(tilt_x), y + z sin(tilt_y)), z cos(tilt).
  bool has_gauge_tilt = false;
  LeadError lead;  // measured on the sphere with a lead given: moves (x, y) with the axes, by the commanded position
  double gauge_tilt_x_urad = 0, gauge_tilt_y_urad = 0, u_gauge_tilt_x_urad = 0, u_gauge_tilt_y_urad = 0;
  double sphere_diameter_mm = 0;  // the certificate's
  size_t sphere_points = 0;
  double sphere_rms_mm = 0;
  std::string gauge_created_utc;
  // The gauge's scale from a step gauge (step_gauge_calibration.h), when measured: last of all, a
  // point's z becomes z / (1 + scale), and its sigma gains z u_scale.
  bool has_gauge_scale = false;
  double gauge_scale_ppm = 0, u_gauge_scale_ppm = 0;
  size_t scale_steps = 0;
  double scale_rms_mm = 0;
  std::string scale_created_utc;
  bool has_version_2_parts() const { return has_gauge_tilt || has_gauge_scale; }
  int version() const {
    return (has_axes && straightness.measured) || lead.measured ? kVersion
           : has_version_2_parts()                            ? kVersionWithTilt
                                                              : kVersionWithoutTilt;
  }

  double x1_mm() const { return x0_mm + step_x_mm * static_cast<double>(nx - 1); }
  double y1_mm() const { return y0_mm + step_y_mm * static_cast<double>(ny - 1); }
  bool covers(double x_mm, double y_mm) const;
  // Bilinear between the nodes; only where covers().
  double z_error_at(double x_mm, double y_mm) const;
  // The four nodes around (x, y) and their bilinear weights (summing to 1).
  void node_weights(double x_mm, double y_mm, size_t (&node)[4], double (&weight)[4]) const;
  double u_at(double x_mm, double y_mm) const;
};

std::string calibration_to_json(const TableCalibration& c);
// Checks everything a correction relies on: version, a grid of at least 2 x 2 nodes with positive
// steps, one finite value and uncertainty per node. `name` is used in messages.
TableCalibration calibration_from_json(const std::string& text, const std::string& name);
// `text`, when given, gets the file's text as read (for a scan file's calibration record).
TableCalibration read_calibration_file(const std::string& path, std::string* text = nullptr);

// A table's errors are its own: a calibration measured on one device corrects no other. Throws a
// CalibrationError naming both devices when the calibration at `path` was measured on
// `measured_on` (its device_id) and `device_id` (the device a scan comes from) is another. Either
// unknown (""): no check, since there is nothing to compare.
void check_calibration_device(const std::string& measured_on, const std::string& path, const std::string& device_id);

// Subtracts the travel's error from every point's z, moves its (x, y) by the axes' errors, the
// screws' periodic error and the gauge's tilt and scales its z by the gauge's scale where they were measured, and adds the map's uncertainty to each point's sigma, where the cloud has one. A point outside the calibrated travel is an error that names it:
// its correction is unknown, and an uncorrected point among corrected ones would be a false number.
void apply_calibration(const TableCalibration& c, PointCloud& cloud, const std::string& name);

// A stored scan corrected by its own calibration record, if it has one: every point's z (to the
// nanometre) and, where given (one per point), its sigma. Returns the calibration applied.
std::optional<TableCalibration> correct_by_record(ScanData& scan, std::vector<double>* sigma_mm, const std::string& name);

}  // namespace dg::host
