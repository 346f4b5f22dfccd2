// The axes' scale and squareness measured on a ball plate: each ball's centre fitted from a scan
// of the plate, and the certified centres matched by the table's axis errors and the plate's
// placement.
#pragma once
#include <string>
#include <vector>

#include "host/geometry/trimmed_face.h"
#include "host/scan/point_reader.h"
#include "host/scan/table_calibration.h"

namespace dg::host {

struct AxisCalibration {
  // Where the table really is for a commanded (x, y): x' = x (1 + scale_x) + y sin(squareness),
  // y' = y (1 + scale_y) cos(squareness); the x axis is the reference direction.
  double scale_x_ppm = 0, scale_y_ppm = 0, squareness_urad = 0;
  double u_scale_x_ppm = 0, u_scale_y_ppm = 0, u_squareness_urad = 0;  // standard uncertainties (k = 1)
  // Where the plate has three rows and three columns: x' and y' gain the ways' bows as well.
  Straightness straightness;
  double placement_deg = 0;        // the plate's rotation on the table (its setup, taken out)
  double centre_rms_mm = 0;        // RMS of the centres' misfit after the fit
  std::vector<Point3> centres;     // each ball's fitted centre, in commanded table coordinates
};

// Each ball's centre, in the scan's coordinates, for balls expected near `expected` (within 8 mm):
// the highest reading there, then a sphere fitted (least squares, algebraic) to the readings within
// 4.5 mm of that top and less than 3.5 mm below it. Throws CalibrationError naming a ball that
// cannot be fitted.
std::vector<Point3> fit_ball_centres(const PointCloud& scan, const std::vector<Point2>& expected, const std::string& name);

// `certified`: the balls' centres in the plate's own frame (x, y, mm; its certificate), with the
// plate laid on the table so that frame matches the table's within 2 mm and a few degrees.
// Each ball's centre as fit_ball_centres finds it; the centres then fit c = R(phi) M(m) + t (M the axes' errors above, R and t the placement) by
// least squares; M's linear entries come from the QR factors of the fitted affine map. Needs at least 4
// balls not on one line; throws CalibrationError naming a ball that cannot be fitted.
AxisCalibration calibrate_from_ball_plate(const PointCloud& scan, const std::vector<Point2>& certified, const std::string& name);

// The certificate: a CSV of x_mm,y_mm per ball (a header line allowed). Throws CalibrationError.
std::vector<Point2> read_ball_certificate(const std::string& path);

}  // namespace dg::host
