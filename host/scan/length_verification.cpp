// Ball-to-ball lengths of a placed ball plate against their certified values.
#include "host/scan/length_verification.h"

#include <cmath>

#include "host/scan/ball_plate_calibration.h"
#include "host/scan/table_calibration.h"

namespace dg::host {

std::vector<Point2> placed_centres(const std::vector<Point2>& certified, double at_x_mm, double at_y_mm, double angle_deg) {
  const double a = angle_deg * 3.14159265358979323846 / 180.0, c = std::cos(a), s = std::sin(a);
  std::vector<Point2> out;
  for (const Point2& p : certified) out.push_back({at_x_mm + c * p.x - s * p.y, at_y_mm + s * p.x + c * p.y});
  return out;
}

LengthVerification verify_lengths(const PointCloud& scan, const std::vector<Point2>& certified, double at_x_mm, double at_y_mm,
                                  double angle_deg, const PermissibleError& mpe, double shortest_mm, const std::string& name) {
  LengthVerification out;
  out.centres = fit_ball_centres(scan, placed_centres(certified, at_x_mm, at_y_mm, angle_deg), name);
  out.pass = true;
  for (size_t i = 0; i < certified.size(); ++i) {
    for (size_t j = i + 1; j < certified.size(); ++j) {
      MeasuredLength l;
      l.from = i, l.to = j;
      l.certified_mm = std::hypot(certified[j].x - certified[i].x, certified[j].y - certified[i].y);
      if (l.certified_mm < shortest_mm) continue;
      l.measured_mm = std::hypot(out.centres[j].x - out.centres[i].x, out.centres[j].y - out.centres[i].y);
      const double e = std::fabs(l.error_mm());
      out.worst_error_mm = std::fmax(out.worst_error_mm, e);
      out.worst_share = std::fmax(out.worst_share, e / mpe.at_mm(l.certified_mm));
      out.pass = out.pass && e <= mpe.at_mm(l.certified_mm);
      out.lengths.push_back(l);
    }
  }
  if (out.lengths.empty()) throw CalibrationError(name + ": no two balls are far enough apart to test a length");
  return out;
}

}  // namespace dg::host
