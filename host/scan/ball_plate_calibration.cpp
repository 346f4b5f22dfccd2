// Ball centres by sphere fits, and the axes' errors from their certified positions.
#include "host/scan/ball_plate_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "host/scan/certificate_csv.h"
#include "host/scan/small_solve.h"
#include "host/scan/sphere_fit.h"
#include "host/scan/table_calibration.h"

namespace dg::host {

namespace {

constexpr double kSearchMm = 8.0;   // the plate's placement error it tolerates, plus a ball's footprint
constexpr double kCapMm = 4.5;      // readings this far from a ball's top in XY belong to its cap
constexpr double kCapDepthMm = 3.5; // and less than this below the top (the plate stays out)
constexpr size_t kMinCapPoints = 12;
constexpr double kMinBallRiseMm = 1.0;

}  // namespace

std::vector<Point3> fit_ball_centres(const PointCloud& scan, const std::vector<Point2>& expected, const std::string& name) {
  std::vector<Point3> centres;
  std::vector<Point3> cap;
  for (size_t k = 0; k < expected.size(); ++k) {
    const Point2& c = expected[k];
    const Point3* top = nullptr;
    for (const Point3& p : scan.points) {
      if (std::hypot(p.x - c.x, p.y - c.y) <= kSearchMm && (top == nullptr || p.z > top->z)) top = &p;
    }
    char where[128];
    std::snprintf(where, sizeof where, "ball %zu (expected at %.3f, %.3f mm)", k + 1, c.x, c.y);
    if (top == nullptr) throw CalibrationError(name + ": " + where + " has no readings within 8 mm; scan the whole plate");
    cap.clear();
    for (const Point3& p : scan.points) {
      if (std::hypot(p.x - top->x, p.y - top->y) <= kCapMm && p.z > top->z - kCapDepthMm) cap.push_back(p);
    }
    // A ball stands proud of its plate: readings that stay within a millimetre of the highest one
    // are the plate (or another flat face), and a sphere through them is no ball's centre.
    double lowest = top->z;
    for (const Point3& p : cap) lowest = std::fmin(lowest, p.z);
    if (top->z - lowest < kMinBallRiseMm) {
      throw CalibrationError(name + ": " + where + ": no ball there (the readings within 4.5 mm of the highest rise " +
                             std::to_string(top->z - lowest) + " mm); is the plate where it is said to be?");
    }
    Point3 centre;
    double radius = 0;
    if (cap.size() < kMinCapPoints || !fit_sphere_algebraic(cap, *top, centre, radius) || radius < 0.5 || radius > 100) {
      throw CalibrationError(name + ": " + where + ": " + std::to_string(cap.size()) +
                             " readings on its cap do not determine a sphere; scan the plate at 1 mm or finer");
    }
    centres.push_back(centre);
  }
  return centres;
}

AxisCalibration calibrate_from_ball_plate(const PointCloud& scan, const std::vector<Point2>& certified, const std::string& name) {
  if (certified.size() < 4) throw CalibrationError("a ball plate needs at least 4 certified balls, got " + std::to_string(certified.size()));
  AxisCalibration out;
  out.centres = fit_ball_centres(scan, certified, name);
  // c = A m + t: two 3-parameter least-squares problems with the same design [m_x, m_y, 1].
  double n[4][4] = {}, bx[4] = {}, by[4] = {};
  for (size_t k = 0; k < certified.size(); ++k) {
    const double row[3] = {out.centres[k].x, out.centres[k].y, 1};
    for (int i = 0; i < 3; ++i) {
      bx[i] += row[i] * certified[k].x, by[i] += row[i] * certified[k].y;
      for (int j = 0; j < 3; ++j) n[i][j] += row[i] * row[j];
    }
  }
  double ax[4] = {}, ay[4] = {}, variance_factor[4] = {};
  {
    double n1[4][4], n2[4][4];
    std::memcpy(n1, n, sizeof n), std::memcpy(n2, n, sizeof n);
    if (!solve_small(3, n1, bx, ax) || !solve_small(3, n2, by, ay) || !inverse_diagonal(3, n, variance_factor)) {
      throw CalibrationError(name + ": the balls' centres lie on one line; the plate needs balls spread in x and y");
    }
  }
  double ss = 0;
  for (size_t k = 0; k < certified.size(); ++k) {
    const Point3& m = out.centres[k];
    const double rx = certified[k].x - (ax[0] * m.x + ax[1] * m.y + ax[2]);
    const double ry = certified[k].y - (ay[0] * m.x + ay[1] * m.y + ay[2]);
    ss += rx * rx + ry * ry;
  }
  const size_t equations = 2 * certified.size();
  out.centre_rms_mm = std::sqrt(ss / static_cast<double>(certified.size()));
  const double sigma2 = equations > 6 ? ss / static_cast<double>(equations - 6) : 0;
  // A = R(phi) U with U upper triangular: phi from A's first column, U = R(-phi) A.
  const double phi = std::atan2(ay[0], ax[0]);
  const double c = std::cos(phi), s = std::sin(phi);
  const double u00 = c * ax[0] + s * ay[0], u01 = c * ax[1] + s * ay[1], u11 = -s * ax[1] + c * ay[1];
  out.placement_deg = phi * 180 / 3.14159265358979323846;
  const double squareness = std::asin(std::clamp(u01, -1.0, 1.0));
  out.scale_x_ppm = (u00 - 1) * 1e6;
  out.squareness_urad = squareness * 1e6;
  out.scale_y_ppm = (u11 / std::cos(squareness) - 1) * 1e6;
  // Each entry's variance is sigma^2 [(D^T D)^-1] on its own diagonal; the rotation by a plate laid
  // within a few degrees mixes the entries little, which this neglects.
  out.u_scale_x_ppm = std::sqrt(sigma2 * variance_factor[0]) * 1e6;
  out.u_squareness_urad = std::sqrt(sigma2 * variance_factor[1]) * 1e6;
  out.u_scale_y_ppm = std::sqrt(sigma2 * variance_factor[1]) * 1e6;
  return out;
}

std::vector<Point2> read_ball_certificate(const std::string& path) {
  std::vector<Point2> out;
  for (const std::vector<double>& row : read_certificate_rows(path, 2, "x_mm,y_mm")) out.push_back({row[0], row[1]});
  if (out.size() < 4) throw CalibrationError(path + ": a ball plate's certificate needs at least 4 balls, it has " + std::to_string(out.size()));
  return out;
}

}  // namespace dg::host
