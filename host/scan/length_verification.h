// A length-measurement check in the manner of ISO 10360-2: the distances between a ball plate's
// balls, measured on a corrected scan, against their certified values and a stated maximum
// permissible error.
#pragma once
#include <string>
#include <vector>

#include "host/geometry/trimmed_face.h"
#include "host/scan/point_reader.h"
#include "host/scan/step_gauge_calibration.h"

namespace dg::host {

// E_MPE = A + L / K, micrometres with L in millimetres (ISO 10360-2's form, e.g. 3 + L/250 um).
struct PermissibleError {
  double a_um = 3;
  double k = 250;
  double at_mm(double length_mm) const { return (a_um + length_mm / k) * 1e-3; }
};

struct MeasuredLength {
  size_t from = 0, to = 0;  // ball (or step) indices (0-based) in the certificate's order
  double certified_mm = 0, measured_mm = 0;
  double error_mm() const { return measured_mm - certified_mm; }
};

struct LengthVerification {
  std::vector<Point3> centres;  // each ball's fitted centre in the scan's (corrected) coordinates
  std::vector<MeasuredLength> lengths;  // every pair of balls (or steps) at least `shortest_mm` apart
  double worst_error_mm = 0;   // the largest |E|
  double worst_share = 0;      // the largest |E| / E_MPE(L)
  bool pass = false;           // every |E| within its E_MPE
  // Adds a length and judges it against `mpe`.
  void add(const MeasuredLength& l, const PermissibleError& mpe);
};

// The plate lies with its own frame's origin at (at_x, at_y) on the table and its x axis `angle_deg`
// anticlockwise from the table's; each ball is looked for where that puts it. Lengths are the
// centres' distances in the table's plane. Throws CalibrationError naming a ball it cannot fit.
LengthVerification verify_lengths(const PointCloud& scan, const std::vector<Point2>& certified, double at_x_mm, double at_y_mm,
                                  double angle_deg, const PermissibleError& mpe, double shortest_mm, const std::string& name);

// The heights between every two steps of a step gauge measured by measure_steps (each against the
// plate beside it), in the certificate's order, against the certified differences: the same check
// along z. `from` and `to` are step indices. Lengths shorter than `shortest_mm` are left out.
LengthVerification verify_heights(const std::vector<StepLevel>& steps, const std::vector<double>& certified,
                                  const PermissibleError& mpe, double shortest_mm);

// Where the plate's balls should be on the table for that placement.
std::vector<Point2> placed_centres(const std::vector<Point2>& certified, double at_x_mm, double at_y_mm, double angle_deg);

}  // namespace dg::host
