// The table's position uncertainty carried into each point's height through the part's slope there.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "host/scan/scan_sink.h"
#include "host/scan/table_calibration.h"

namespace dg::host {

// A point read at (x, y) where the table may stand u_x, u_y off has a height uncertain by the
// slope times that: u_z^2 = (dz/dx u_x)^2 + (dz/dy u_y)^2 (GUM 5.1.2, first order). u_x and u_y
// combine the motor step q (a rectangular distribution over one step, q^2 / 12: where between two
// steps the rotor stands under load is not known) and, when the table was calibrated on a ball
// plate, the uncertainty of the scale and squareness it corrects by: (x u_sx)^2 + (y u_q)^2 along
// x and (y u_sy)^2 along y; when the gauge's tilt was measured on a sphere, the reading's height z
// times the tilt's uncertainty, (z u_tx)^2 and (z u_ty)^2 (the shear it corrects by); when the
// plate measured the ways' straightness, each bow's uncertainty where the point lies (it grows with
// the square of the distance from the plate's middle), and the screws' periodic error's where the
// sphere measured one. The repeatability measured at the scan's
// first point holds this only for that point's slope, which is usually none.
struct TablePosition {
  double step_mm = 0;                            // the axes' travel per motor step
  double u_scale_x = 0, u_scale_y = 0;           // relative (ppm * 1e-6)
  double u_squareness_rad = 0;
  double u_tilt_x_rad = 0, u_tilt_y_rad = 0;
  Straightness straightness;                     // its u_x_um and u_y_um (measured: with a bow)
  LeadError lead;                                // the screws' periodic error's u (measured: with one)
  double u_x_mm(double x_mm, double y_mm, double z_mm) const;
  double u_y_mm(double x_mm, double y_mm, double z_mm) const;
};

// What the scan's device record and its calibration (its axes and gauge tilt) say about the table.
TablePosition table_position(const ScanData& scan, const std::optional<TableCalibration>& calibration);

// The slope at every point of a scan from its neighbours: the previous and next point on its line
// and the nearest point on each neighbouring line, by least squares over those differences (so
// the lines' direction does not matter). A point with too few neighbours in two directions gets
// the slope along the one it has. {dz/dx, dz/dy} per point, in the points' order.
std::vector<std::pair<double, double>> scan_slopes(const ScanData& scan);

// Adds the position term to `sigma_mm` (one per point of `scan`, its points corrected already).
// Returns how much it added at most (0 when the table's position is not known to be uncertain).
double add_position_uncertainty(const ScanData& scan, const TablePosition& table, std::vector<double>& sigma_mm);

}  // namespace dg::host
