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

namespace {

// How many distinct values (more than 1 mm apart) `values` holds: a plate's rows or columns.
size_t distinct_rows(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  size_t rows = values.empty() ? 0 : 1;
  for (size_t k = 1; k < values.size(); ++k) rows += values[k] - values[k - 1] > 1.0 ? 1 : 0;
  return rows;
}

// The least-squares fit of every ball's certified centre c = A m + t + R(phi) (k_x Qy, k_y Qx),
// Qy = (m_y - centre_y)^2 and Qx = (m_x - centre_x)^2, for the unknowns (A's first row, t_x, A's
// second row, t_y[, k_x, k_y]) in that order. One system for both coordinates: the bows, which
// belong to the table, reach both through the plate's rotation.
struct PlateFit {
  double p[8] = {};
  double variance_factor[8] = {};
  double ss = 0;  // the residuals' sum of squares (mm^2)
  bool ok = false;
};

PlateFit fit_plate(const std::vector<Point3>& m, const std::vector<Point2>& certified, int unknowns, double phi,
                   double centre_x, double centre_y) {
  PlateFit fit;
  double n[8][8] = {}, b[8] = {};
  const double c = std::cos(phi), s = std::sin(phi);
  auto rows = [&](size_t k, double (&rx)[8], double (&ry)[8]) {
    const double qy = (m[k].y - centre_y) * (m[k].y - centre_y), qx = (m[k].x - centre_x) * (m[k].x - centre_x);
    const double x_row[8] = {m[k].x, m[k].y, 1, 0, 0, 0, c * qy, -s * qx};
    const double y_row[8] = {0, 0, 0, m[k].x, m[k].y, 1, s * qy, c * qx};
    for (int i = 0; i < 8; ++i) rx[i] = x_row[i], ry[i] = y_row[i];
  };
  for (size_t k = 0; k < certified.size(); ++k) {
    double rx[8], ry[8];
    rows(k, rx, ry);
    for (int i = 0; i < unknowns; ++i) {
      b[i] += rx[i] * certified[k].x + ry[i] * certified[k].y;
      for (int j = 0; j < unknowns; ++j) n[i][j] += rx[i] * rx[j] + ry[i] * ry[j];
    }
  }
  double solve[8][8];
  std::memcpy(solve, n, sizeof n);
  if (!solve_small(unknowns, solve, b, fit.p) || !inverse_diagonal(unknowns, n, fit.variance_factor)) return fit;
  for (size_t k = 0; k < certified.size(); ++k) {
    double rx[8], ry[8];
    rows(k, rx, ry);
    double px = 0, py = 0;
    for (int i = 0; i < unknowns; ++i) px += rx[i] * fit.p[i], py += ry[i] * fit.p[i];
    fit.ss += (certified[k].x - px) * (certified[k].x - px) + (certified[k].y - py) * (certified[k].y - py);
  }
  fit.ok = true;
  return fit;
}

}  // namespace

AxisCalibration calibrate_from_ball_plate(const PointCloud& scan, const std::vector<Point2>& certified, const std::string& name) {
  if (certified.size() < 4) throw CalibrationError("a ball plate needs at least 4 certified balls, got " + std::to_string(certified.size()));
  AxisCalibration out;
  out.centres = fit_ball_centres(scan, certified, name);
  // A bow needs three rows (and three columns) to be told from a straight, leaning axis.
  std::vector<double> xs, ys;
  for (const Point2& c : certified) xs.push_back(c.x), ys.push_back(c.y);
  Straightness& bow = out.straightness;
  bow.measured = distinct_rows(xs) >= 3 && distinct_rows(ys) >= 3;
  double lo_x = out.centres[0].x, hi_x = lo_x, lo_y = out.centres[0].y, hi_y = lo_y;
  for (const Point3& m : out.centres) {
    lo_x = std::fmin(lo_x, m.x), hi_x = std::fmax(hi_x, m.x), lo_y = std::fmin(lo_y, m.y), hi_y = std::fmax(hi_y, m.y);
  }
  bow.centre_x_mm = 0.5 * (lo_x + hi_x), bow.centre_y_mm = 0.5 * (lo_y + hi_y);
  bow.half_span_x_mm = 0.5 * (hi_x - lo_x), bow.half_span_y_mm = 0.5 * (hi_y - lo_y);
  const int unknowns = bow.measured ? 8 : 6;
  // The bows reach the plate's frame turned by its placement: a first fit finds the placement, a
  // second fits the bows along it (its change mixes the bows by the sine of a few microradians).
  PlateFit fit = fit_plate(out.centres, certified, unknowns, 0, bow.centre_x_mm, bow.centre_y_mm);
  if (fit.ok) fit = fit_plate(out.centres, certified, unknowns, std::atan2(fit.p[3], fit.p[0]), bow.centre_x_mm, bow.centre_y_mm);
  if (!fit.ok) throw CalibrationError(name + ": the balls' centres lie on one line; the plate needs balls spread in x and y");
  const double* ax = fit.p;
  const double* ay = fit.p + 3;
  const size_t equations = 2 * certified.size();
  out.centre_rms_mm = std::sqrt(fit.ss / static_cast<double>(certified.size()));
  const double sigma2 = equations > static_cast<size_t>(unknowns) ? fit.ss / static_cast<double>(equations - static_cast<size_t>(unknowns)) : 0;
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
  out.u_scale_x_ppm = std::sqrt(sigma2 * fit.variance_factor[0]) * 1e6;
  out.u_squareness_urad = std::sqrt(sigma2 * fit.variance_factor[1]) * 1e6;
  out.u_scale_y_ppm = std::sqrt(sigma2 * fit.variance_factor[4]) * 1e6;
  if (bow.measured) {
    // The sagitta over the outer balls' span: how far the path at mid-span lies from the chord
    // through its ends, k h^2 with the opposite sign (k the bow's curvature term).
    const double hy2 = bow.half_span_y_mm * bow.half_span_y_mm, hx2 = bow.half_span_x_mm * bow.half_span_x_mm;
    bow.x_um = -fit.p[6] * hy2 * 1e3;
    bow.y_um = -fit.p[7] * hx2 * 1e3;
    bow.u_x_um = std::sqrt(sigma2 * fit.variance_factor[6]) * hy2 * 1e3;
    bow.u_y_um = std::sqrt(sigma2 * fit.variance_factor[7]) * hx2 * 1e3;
  }
  return out;
}

std::vector<Point2> read_ball_certificate(const std::string& path) {
  std::vector<Point2> out;
  for (const std::vector<double>& row : read_certificate_rows(path, 2, "x_mm,y_mm")) out.push_back({row[0], row[1]});
  if (out.size() < 4) throw CalibrationError(path + ": a ball plate's certificate needs at least 4 balls, it has " + std::to_string(out.size()));
  return out;
}

}  // namespace dg::host
