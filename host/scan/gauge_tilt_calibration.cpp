// The gauge's tilt from a reference sphere: a Gauss-Newton fit of the sphere's cap with the
// plunger's lean among the unknowns.
#include "host/scan/gauge_tilt_calibration.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

#include "host/scan/small_solve.h"
#include "host/scan/sphere_fit.h"

namespace dg::host {

namespace {

constexpr double kCapAngleRad = 55 * 3.14159265358979323846 / 180;  // steeper, a plunger drags sideways
constexpr size_t kMinCapPoints = 50;
constexpr double kMaxRmsMm = 0.010;
constexpr double kMaxTiltRad = 0.05;  // a stand leaning more than 2.9 degrees is broken, not out of true
constexpr int kUnknowns = 9;  // the centre (x, y, z), the tilt's sin x, sin y, and the screws' periodic error
constexpr int kTiltUnknowns = 5;  // without the screws'
constexpr double kPi = 3.14159265358979323846;

// The cap in coordinates relative to its highest reading, for conditioning. A point's reading
// height z enters the shear only by differences: its offset from the top moves the centre. The
// screws' error goes by the table's position: its sine and cosine less one (nothing at the
// origin) at x and y for one turn of the given lead, or none.
struct CapPoint {
  double x, y, z;
  double sin_x = 0, cos_x = 0, sin_y = 0, cos_y = 0;
};

// Each reading's distance from the sphere less the radius, and its gradient in the unknowns.
// q = (cx, cy, cz, sx, sy, a_x, b_x, a_y, b_y); the reading touches (x + z sx + e_x, y + z sy +
// e_y, z cos) with e_x = a_x sin + b_x (cos - 1) of x's phase in the screw's turn, e_y the same in y
// (docs/calibration.md). Without the screws' terms their entries stay 0.
double residual(const CapPoint& p, const double (&q)[kUnknowns], double radius_mm, double (*gradient)[kUnknowns]) {
  const double cos_tilt = std::sqrt(1 - q[3] * q[3] - q[4] * q[4]);
  const double ex = q[5] * p.sin_x + q[6] * p.cos_x, ey = q[7] * p.sin_y + q[8] * p.cos_y;
  const double ux = p.x + p.z * q[3] + ex - q[0], uy = p.y + p.z * q[4] + ey - q[1], uz = p.z * cos_tilt - q[2];
  const double d = std::sqrt(ux * ux + uy * uy + uz * uz);
  if (gradient != nullptr) {
    (*gradient)[0] = -ux / d, (*gradient)[1] = -uy / d, (*gradient)[2] = -uz / d;
    (*gradient)[3] = p.z * (ux - uz * q[3] / cos_tilt) / d;
    (*gradient)[4] = p.z * (uy - uz * q[4] / cos_tilt) / d;
    (*gradient)[5] = ux / d * p.sin_x, (*gradient)[6] = ux / d * p.cos_x;
    (*gradient)[7] = uy / d * p.sin_y, (*gradient)[8] = uy / d * p.cos_y;
  }
  return d - radius_mm;
}

double sum_of_squares(const std::vector<CapPoint>& cap, const double (&q)[kUnknowns], double radius_mm) {
  double ss = 0;
  for (const CapPoint& p : cap) {
    const double r = residual(p, q, radius_mm, nullptr);
    ss += r * r;
  }
  return ss;
}

// J^T J and J^T f at q.
// The leading n x n block: the entries beyond it stay 0 (and the unknowns beyond it unused).
void normal_equations(const std::vector<CapPoint>& cap, const double (&q)[kUnknowns], double radius_mm, int n,
                      double (&jtj)[kUnknowns][kUnknowns], double (&jtf)[kUnknowns]) {
  for (int i = 0; i < kUnknowns; ++i) {
    jtf[i] = 0;
    for (int j = 0; j < kUnknowns; ++j) jtj[i][j] = 0;
  }
  double g[kUnknowns];
  for (const CapPoint& p : cap) {
    const double f = residual(p, q, radius_mm, &g);
    for (int i = 0; i < n; ++i) {
      jtf[i] += g[i] * f;
      for (int j = 0; j < n; ++j) jtj[i][j] += g[i] * g[j];
    }
  }
}

// The variance the map's node uncertainties give unknown `which` of the fit at q. A node's error
// e_k moves every reading over its cells by -w_ik e_k (its bilinear weight), each residual by
// df_i/dz_i times that, and the fit by -(J^T J)^-1 J^T of those: a sensitivity s_k per node, and
// a variance sum_k (s_k u_k)^2.
double tilt_variance_from_map(const std::vector<CapPoint>& cap, const std::vector<Point3>& at, const double (&q)[kUnknowns],
                              double radius_mm, int n, const double (&jtj)[kUnknowns][kUnknowns], const TableCalibration& map,
                              int which) {
  // Row `which` of (J^T J)^-1 (symmetric: its column).
  double a[kUnknowns][kUnknowns], unit[kUnknowns] = {}, row[kUnknowns] = {};
  for (int i = 0; i < kUnknowns; ++i)
    for (int j = 0; j < kUnknowns; ++j) a[i][j] = jtj[i][j];
  unit[which] = 1;
  if (!solve_small(n, a, unit, row)) return 0;
  std::map<size_t, double> sensitivity;
  const double cos_tilt = std::sqrt(1 - q[3] * q[3] - q[4] * q[4]);
  double g[kUnknowns];
  for (size_t i = 0; i < cap.size(); ++i) {
    const CapPoint& p = cap[i];
    residual(p, q, radius_mm, &g);
    // The centre's gradient is -u / |u|; a reading moved by dz moves the touched point by
    // dz (sx, sy, cos), so df/dz is u / |u| along that.
    const double df_dz = -(g[0] * q[3] + g[1] * q[4] + g[2] * cos_tilt);
    double row_dot_g = 0;
    for (int k = 0; k < n; ++k) row_dot_g += row[k] * g[k];
    size_t node[4];
    double weight[4];
    map.node_weights(at[i].x, at[i].y, node, weight);
    // dq = -(J^T J)^-1 g_i df_i and df_i = df_dz (-w e): the two signs cancel.
    for (int k = 0; k < 4; ++k) sensitivity[node[k]] += row_dot_g * df_dz * weight[k];
  }
  double variance = 0;
  for (const auto& [node, s] : sensitivity) variance += s * s * map.u_mm[node] * map.u_mm[node];
  return variance;
}

}  // namespace

double sphere_cap_reach_mm(double diameter_mm) { return diameter_mm / 2 * std::sin(kCapAngleRad); }

GaugeTilt calibrate_gauge_tilt(const PointCloud& scan, double diameter_mm, const std::string& name, const TableCalibration* map,
                               double lead_mm) {
  if (!(diameter_mm > 1 && diameter_mm < 200)) {
    throw CalibrationError(name + ": a reference sphere's diameter must lie between 1 and 200 mm");
  }
  if (lead_mm != 0 && !(lead_mm >= 0.5 && lead_mm <= 100)) throw CalibrationError(name + ": a screw's lead must lie between 0.5 and 100 mm");
  const int n = lead_mm > 0 ? kUnknowns : kTiltUnknowns;
  const double radius_mm = diameter_mm / 2;
  const Point3* top = nullptr;
  for (const Point3& p : scan.points) {
    if (top == nullptr || p.z > top->z) top = &p;
  }
  if (top == nullptr) throw CalibrationError(name + ": no readings");
  // The cap: within the cap angle of the top, sideways and in depth (the stem and the base below
  // the sphere's equator stay out).
  const double reach_mm = sphere_cap_reach_mm(diameter_mm), depth_mm = radius_mm * (1 - std::cos(kCapAngleRad));
  std::vector<CapPoint> cap;
  std::vector<Point3> cap_points;
  double lowest = 0;
  for (const Point3& p : scan.points) {
    if (std::hypot(p.x - top->x, p.y - top->y) > reach_mm || p.z < top->z - depth_mm - 0.5) continue;
    CapPoint c{p.x - top->x, p.y - top->y, p.z - top->z};
    if (lead_mm > 0) {
      const double turn_x = 2 * kPi * p.x / lead_mm, turn_y = 2 * kPi * p.y / lead_mm;
      c.sin_x = std::sin(turn_x), c.cos_x = std::cos(turn_x) - 1, c.sin_y = std::sin(turn_y), c.cos_y = std::cos(turn_y) - 1;
    }
    cap.push_back(c);
    cap_points.push_back(p);
    lowest = std::fmin(lowest, p.z - top->z);
  }
  char words[256];
  if (cap.size() < kMinCapPoints) {
    std::snprintf(words, sizeof words, ": %zu readings lie on the sphere's cap (within %.1f mm of its top at (%.3f, %.3f)); "
                  "the tilt needs %zu: scan the whole sphere at 1 mm or finer", cap.size(), reach_mm, top->x, top->y, kMinCapPoints);
    throw CalibrationError(name + words);
  }
  if (std::fabs(lowest) < 0.25 * radius_mm) {
    std::snprintf(words, sizeof words, ": the readings around the top reach only %.2f mm below it; a %.1f mm sphere's cap goes "
                  "%.2f mm down: is the sphere under the gauge, and the whole of it scanned?", std::fabs(lowest), diameter_mm, depth_mm);
    throw CalibrationError(name + words);
  }
  Point3 centre;
  double free_radius = 0;
  if (!fit_sphere_algebraic(cap_points, *top, centre, free_radius) || std::fabs(2 * free_radius - diameter_mm) > 0.02 * diameter_mm) {
    std::snprintf(words, sizeof words, ": the readings give a sphere %.3f mm across, the certificate says %.3f mm: is this the "
                  "certified sphere, clean, and the right diameter given?", 2 * free_radius, diameter_mm);
    throw CalibrationError(name + words);
  }
  double q[kUnknowns] = {centre.x - top->x, centre.y - top->y, centre.z - top->z};
  double ss = sum_of_squares(cap, q, radius_mm);
  bool converged = false;
  for (int iteration = 0; iteration < 100 && !converged; ++iteration) {
    double jtj[kUnknowns][kUnknowns], jtf[kUnknowns], step[kUnknowns];
    normal_equations(cap, q, radius_mm, n, jtj, jtf);
    for (double& v : jtf) v = -v;
    if (!solve_small(n, jtj, jtf, step)) break;
    // Halve the step until it lowers the misfit (Gauss-Newton overshoots far from the minimum). A
    // Gauss-Newton step is downhill, so none lowering it means the misfit is at its minimum to rounding.
    converged = true;
    for (double scale = 1; scale > 1e-6; scale /= 2) {
      double trial[kUnknowns] = {};
      for (int i = 0; i < n; ++i) trial[i] = q[i] + scale * step[i];
      if (trial[3] * trial[3] + trial[4] * trial[4] >= 1) continue;
      const double trial_ss = sum_of_squares(cap, trial, radius_mm);
      if (trial_ss <= ss) {
        for (int i = 0; i < n; ++i) q[i] = trial[i];
        converged = trial_ss >= ss * (1 - 1e-12) || (std::fabs(scale * step[3]) < 1e-10 && std::fabs(scale * step[4]) < 1e-10 &&
                                                      std::fabs(scale * step[0]) + std::fabs(scale * step[1]) + std::fabs(scale * step[2]) < 1e-9);
        ss = trial_ss;
        break;
      }
    }
  }
  GaugeTilt out;
  out.points = cap.size();
  out.free_diameter_mm = 2 * free_radius;
  out.residual_rms_mm = std::sqrt(ss / static_cast<double>(cap.size()));
  double jtj[kUnknowns][kUnknowns], jtf[kUnknowns], variance_factor[kUnknowns] = {};
  normal_equations(cap, q, radius_mm, n, jtj, jtf);
  if (!converged || !inverse_diagonal(n, jtj, variance_factor) || !std::isfinite(ss)) {
    throw CalibrationError(name + ": the sphere's fit did not settle; scan the sphere again, the whole of its top");
  }
  if (out.residual_rms_mm > kMaxRmsMm) {
    std::snprintf(words, sizeof words, ": the readings lie %.4f mm RMS off a %.3f mm sphere even with the tilt fitted (more "
                  "than %.3f mm): is the sphere clean, the stand firm, the diameter right?", out.residual_rms_mm, diameter_mm, kMaxRmsMm);
    throw CalibrationError(name + words);
  }
  if (std::hypot(q[3], q[4]) > kMaxTiltRad) {
    std::snprintf(words, sizeof words, ": the gauge leans %.1f mrad (%.2f degrees): a stand this far out of true binds the "
                  "plunger; set it upright and calibrate again", std::hypot(q[3], q[4]) * 1e3, std::asin(std::hypot(q[3], q[4])) * 57.29578);
    throw CalibrationError(name + words);
  }
  const double sigma2 = ss / static_cast<double>(cap.size() - static_cast<size_t>(n));
  out.tilt_x_urad = std::asin(q[3]) * 1e6, out.tilt_y_urad = std::asin(q[4]) * 1e6;
  // d asin(s) / ds = 1 / cos: 1 within 1e-3 for any tilt accepted.
  const double to_urad[2] = {1e6 / std::sqrt(1 - q[3] * q[3]), 1e6 / std::sqrt(1 - q[4] * q[4])};
  out.u_noise_x_urad = std::sqrt(sigma2 * variance_factor[3]) * to_urad[0];
  out.u_noise_y_urad = std::sqrt(sigma2 * variance_factor[4]) * to_urad[1];
  if (map != nullptr) {
    const double u_map_sq[2] = {tilt_variance_from_map(cap, cap_points, q, radius_mm, n, jtj, *map, 3),
                                tilt_variance_from_map(cap, cap_points, q, radius_mm, n, jtj, *map, 4)};
    out.u_map_x_urad = std::sqrt(u_map_sq[0]) * to_urad[0], out.u_map_y_urad = std::sqrt(u_map_sq[1]) * to_urad[1];
  }
  out.u_tilt_x_urad = std::hypot(out.u_noise_x_urad, out.u_map_x_urad);
  out.u_tilt_y_urad = std::hypot(out.u_noise_y_urad, out.u_map_y_urad);
  if (lead_mm > 0) {
    LeadError& lead = out.lead;
    lead.measured = true;
    lead.lead_mm = lead_mm;
    lead.x_sin_um = q[5] * 1e3, lead.x_cos_um = q[6] * 1e3, lead.y_sin_um = q[7] * 1e3, lead.y_cos_um = q[8] * 1e3;
    // The larger of each pair's u: the amplitude's u whatever the phase (the two are nearly
    // independent over whole turns of the screw).
    lead.u_x_um = std::sqrt(sigma2 * std::fmax(variance_factor[5], variance_factor[6])) * 1e3;
    lead.u_y_um = std::sqrt(sigma2 * std::fmax(variance_factor[7], variance_factor[8])) * 1e3;
  }
  // Back to the scan's frame: the top's offsets, with the shear of its own height (see CapPoint).
  const double cos_tilt = std::sqrt(1 - q[3] * q[3] - q[4] * q[4]);
  out.centre_mm[0] = q[0] + top->x + top->z * q[3];
  out.centre_mm[1] = q[1] + top->y + top->z * q[4];
  out.centre_mm[2] = q[2] + top->z * cos_tilt;
  return out;
}

}  // namespace dg::host
