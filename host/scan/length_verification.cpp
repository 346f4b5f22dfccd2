// Ball-to-ball lengths of a placed ball plate, and step-to-step heights of a step gauge, against
// their certified values.
#include "host/scan/length_verification.h"

#include <cmath>

#include "host/scan/ball_plate_calibration.h"
#include "host/scan/step_gauge_calibration.h"
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
      out.add(l, mpe);
    }
  }
  if (out.lengths.empty()) throw CalibrationError(name + ": no two balls are far enough apart to test a length");
  return out;
}

LengthVerification verify_heights(const std::vector<StepLevel>& steps, const std::vector<double>& certified,
                                  const PermissibleError& mpe, double shortest_mm) {
  LengthVerification out;
  out.pass = true;
  for (size_t i = 0; i < certified.size(); ++i) {
    for (size_t j = i + 1; j < certified.size(); ++j) {
      MeasuredLength l;
      l.from = i, l.to = j;
      l.certified_mm = std::fabs(certified[j] - certified[i]);
      if (l.certified_mm < shortest_mm) continue;
      // The measured difference in the certified one's sense: a step read lower than its
      // neighbour when certified higher is a negative length, and its whole error counts.
      l.measured_mm = (steps[j].height_mm - steps[i].height_mm) * (certified[j] >= certified[i] ? 1 : -1);
      out.add(l, mpe);
    }
  }
  return out;
}

void LengthVerification::add(const MeasuredLength& l, const PermissibleError& mpe) {
  const double e = std::fabs(l.error_mm());
  worst_error_mm = std::fmax(worst_error_mm, e);
  worst_share = std::fmax(worst_share, e / mpe.at_mm(l.certified_mm));
  pass = pass && e <= mpe.at_mm(l.certified_mm);
  lengths.push_back(l);
}

}  // namespace dg::host
