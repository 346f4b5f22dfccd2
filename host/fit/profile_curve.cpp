// Hlavova's (2021) curves. Its section 3 keeps, where the trend cubic lies above a point, the offset
// point with the smaller z, and the other where it lies below: the curve goes to the far side of
// each point's uncertainty circle from the trend, which keeps the point's own deviation from the
// trend in the model instead of smoothing it away. The text is followed as written.
#include "host/fit/profile_curve.h"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>

#include "common/fit/bspline_basis.h"
#include "host/fit/fit_error.h"
#include "host/geometry/vec3.h"

namespace dg::host {

namespace {

std::vector<double> chord_parameters(const std::vector<Point3>& p) {
  std::vector<double> t(p.size(), 0.0);
  for (size_t k = 1; k < p.size(); ++k) t[k] = t[k - 1] + norm(p[k] - p[k - 1]);
  return t;
}

// Clamped cubic knots with one interior knot at every interior parameter (the spline's joints).
std::vector<double> joint_knots(const std::vector<double>& t) {
  std::vector<double> k(4, t.front());
  for (size_t i = 1; i + 1 < t.size(); ++i) k.push_back(t[i]);
  k.insert(k.end(), 4, t.back());
  return k;
}

// The span of t and the cubic's four non-zero basis values and first derivatives there.
void basis_row(const std::vector<double>& knots, int count, double t, int* span, double n[4], double d1[4]) {
  *span = fit::find_span(count, 3, t, knots.data());
  fit::bspline_basis(*span, 3, t, knots.data(), n, d1);
}

Point3 derivative(const BSplineCurve& c, double t) {
  double n[4], d1[4];
  int span = 0;
  basis_row(c.knots, static_cast<int>(c.control.size()), t, &span, n, d1);
  Point3 d;
  for (int a = 0; a <= 3; ++a) d += d1[a] * c.control[static_cast<size_t>(span - 3 + a)];
  return d;
}

}  // namespace

void check_profile(const std::vector<Point3>& p, const std::string& name) {
  if (p.size() < 4) {
    throw FitError(name + ": a profile needs at least 4 points (the trend is a cubic); got " + std::to_string(p.size()));
  }
  for (size_t k = 0; k < p.size(); ++k) {
    if (!std::isfinite(p[k].x + p[k].y + p[k].z)) throw FitError(name + ": point " + std::to_string(k + 1) + " is not finite");
    if (std::fabs(p[k].y - p[0].y) > 1e-3) {
      throw FitError(name + ": point " + std::to_string(k + 1) + " leaves the profile's plane y = " + std::to_string(p[0].y) +
                     " (a profile is planar: x and z)");
    }
    if (k > 0 && norm(p[k] - p[k - 1]) <= 0) {
      throw FitError(name + ": points " + std::to_string(k) + " and " + std::to_string(k + 1) + " are the same");
    }
  }
}

ProfileCubic fit_profile_cubic(const std::vector<Point3>& p) {
  Eigen::MatrixXd a(static_cast<Eigen::Index>(p.size()), 4);
  Eigen::VectorXd z(static_cast<Eigen::Index>(p.size()));
  for (size_t k = 0; k < p.size(); ++k) {
    const double x = p[k].x;
    a.row(static_cast<Eigen::Index>(k)) << x * x * x, x * x, x, 1.0;
    z(static_cast<Eigen::Index>(k)) = p[k].z;
  }
  const Eigen::Vector4d c = a.colPivHouseholderQr().solve(z);
  return {c(0), c(1), c(2), c(3)};
}

BSplineCurve interpolate_natural(const std::vector<Point3>& p) {
  const std::vector<double> t = chord_parameters(p);
  BSplineCurve c;
  c.degree = 3;
  c.knots = joint_knots(t);
  const int count = static_cast<int>(p.size()) + 2;
  // Rows: the curve through every point, and zero second derivative at both ends. At a clamped
  // end the second derivative is a multiple of (P2 - P1) / (k5 - k2) - (P1 - P0) / (k4 - k1)
  // (k the knots): the difference of the first two control points of the derivative curve.
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(count, 3);
  for (size_t k = 0; k < p.size(); ++k) {
    double n[4], d1[4];
    int span = 0;
    basis_row(c.knots, count, t[k], &span, n, d1);
    for (int a = 0; a <= 3; ++a) {
      if (n[a] != 0) entries.emplace_back(static_cast<int>(k), span - 3 + a, n[a]);
    }
    rhs.row(static_cast<Eigen::Index>(k)) << p[k].x, p[k].y, p[k].z;
  }
  const std::vector<double>& u = c.knots;
  const int r0 = static_cast<int>(p.size()), r1 = r0 + 1;
  {
    const double e = u[4] - u[1], f = u[5] - u[2];
    entries.emplace_back(r0, 0, 1.0 / e);
    entries.emplace_back(r0, 1, -1.0 / e - 1.0 / f);
    entries.emplace_back(r0, 2, 1.0 / f);
  }
  {
    const size_t m = u.size() - 1;  // the last knot
    const double e = u[m - 1] - u[m - 4], f = u[m - 2] - u[m - 5];
    const int last = count - 1;
    entries.emplace_back(r1, last, 1.0 / e);
    entries.emplace_back(r1, last - 1, -1.0 / e - 1.0 / f);
    entries.emplace_back(r1, last - 2, 1.0 / f);
  }
  Eigen::SparseMatrix<double> m(count, count);
  m.setFromTriplets(entries.begin(), entries.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(m);
  if (lu.info() != Eigen::Success) throw FitError("the interpolation equations are singular (points repeated?)");
  const Eigen::MatrixXd x = lu.solve(rhs);
  for (int i = 0; i < count; ++i) c.control.push_back({x(i, 0), x(i, 1), x(i, 2)});
  return c;
}

namespace {

// The least-squares clamped cubic on parameters t (knots uniform over [t.front(), t.back()]), its
// ends on the first and last point.
BSplineCurve least_squares_clamped(const std::vector<Point3>& p, const std::vector<double>& t, int control_count) {
  BSplineCurve c;
  c.degree = 3;
  c.knots = clamped_uniform_knots(control_count, 3);
  for (double& k : c.knots) k = t.front() + k * (t.back() - t.front());
  // The ends are the end points; the inner control points by least squares (normal equations).
  const int inner = control_count - 2;
  Eigen::MatrixXd ata = Eigen::MatrixXd::Zero(inner, inner);
  Eigen::MatrixXd atb = Eigen::MatrixXd::Zero(inner, 3);
  for (size_t k = 0; k < p.size(); ++k) {
    double n[4], d1[4];
    int span = 0;
    basis_row(c.knots, control_count, t[k], &span, n, d1);
    Eigen::Vector3d target(p[k].x, p[k].y, p[k].z);
    for (int a = 0; a <= 3; ++a) {
      const int i = span - 3 + a;
      if (i == 0) target -= n[a] * Eigen::Vector3d(p.front().x, p.front().y, p.front().z);
      if (i == control_count - 1) target -= n[a] * Eigen::Vector3d(p.back().x, p.back().y, p.back().z);
    }
    for (int a = 0; a <= 3; ++a) {
      const int i = span - 3 + a - 1;
      if (i < 0 || i >= inner) continue;
      atb.row(i) += n[a] * target.transpose();
      for (int b = 0; b <= 3; ++b) {
        const int j = span - 3 + b - 1;
        if (j >= 0 && j < inner) ata(i, j) += n[a] * n[b];
      }
    }
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt = ata.ldlt();
  if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-12)) {
    throw FitError("the points cannot determine " + std::to_string(control_count) +
                   " control points (too few points between the knots); use fewer");
  }
  const Eigen::MatrixXd x = ldlt.solve(atb);
  c.control.push_back(p.front());
  for (int i = 0; i < inner; ++i) c.control.push_back({x(i, 0), x(i, 1), x(i, 2)});
  c.control.push_back(p.back());
  return c;
}

// Newton on the foot-point condition (C(t) - q) . C'(t) = 0 from t, kept within the curve.
double foot_parameter(const BSplineCurve& c, const Point3& q, double t) {
  for (int iteration = 0; iteration < 50; ++iteration) {
    const Point3 d = derivative(c, t);
    const double step = dot(q - c.evaluate(t), d) / std::max(dot(d, d), 1e-300);
    t = std::clamp(t + step, c.t_min(), c.t_max());
    if (std::fabs(step) < 1e-13 * (1 + std::fabs(t))) break;
  }
  return t;
}

// One step of tangent-distance minimization for a profile in a plane y = constant: with each point
// held at its foot parameter t_k on the current curve, the inner control points (x, z) that
// minimize sum ((C(t_k) - p_k) . n_k)^2 + w ((C(t_k) - p_k) . T_k)^2, where n_k and T_k are the
// curve's normal and tangent at the foot point. The normal term is the squared distance to the
// curve's tangent line, a second-order model of the squared distance near the curve; the small
// tangential term (weight 1e-4: at 1e-2 it held Hamdan's boundary at 0.0027 mm for a hundred steps)
// keeps the system determined where the normals alone would not be. It converges in tens of steps
// where moving parameters alone (point-distance minimization) creeps.
BSplineCurve tangent_distance_step(const BSplineCurve& c, const std::vector<Point3>& p, const std::vector<double>& t) {
  const int count = static_cast<int>(c.control.size()), inner = count - 2;
  const double tangential_weight = 0.0001;
  Eigen::MatrixXd ata = Eigen::MatrixXd::Zero(2 * inner, 2 * inner);
  Eigen::VectorXd atb = Eigen::VectorXd::Zero(2 * inner);
  for (size_t k = 0; k < p.size(); ++k) {
    double n[4], d1[4];
    int span = 0;
    basis_row(c.knots, count, t[k], &span, n, d1);
    Point3 tangent = derivative(c, t[k]);
    const double length = std::hypot(tangent.x, tangent.z);
    if (!(length > 0)) continue;
    tangent = {tangent.x / length, 0, tangent.z / length};
    const Point3 normal{-tangent.z, 0, tangent.x};
    for (int side = 0; side < 2; ++side) {
      const Point3& dir = side == 0 ? normal : tangent;
      const double w = side == 0 ? 1.0 : tangential_weight;
      // Row: sum_i N_i (P_i . dir) = p_k . dir, the ends' terms moved to the right.
      double row_x[4] = {}, row_z[4] = {};
      int index[4];
      double rhs = dot(p[k], dir);
      for (int a = 0; a <= 3; ++a) {
        const int i = span - 3 + a;
        index[a] = i - 1;
        if (i == 0 || i == count - 1) {
          rhs -= n[a] * dot(c.control[static_cast<size_t>(i)], dir);
          index[a] = -1;
          continue;
        }
        row_x[a] = n[a] * dir.x;
        row_z[a] = n[a] * dir.z;
      }
      for (int a = 0; a <= 3; ++a) {
        if (index[a] < 0) continue;
        const int ax = 2 * index[a], az = ax + 1;
        atb(ax) += w * row_x[a] * rhs;
        atb(az) += w * row_z[a] * rhs;
        for (int b = 0; b <= 3; ++b) {
          if (index[b] < 0) continue;
          const int bx = 2 * index[b], bz = bx + 1;
          ata(ax, bx) += w * row_x[a] * row_x[b];
          ata(ax, bz) += w * row_x[a] * row_z[b];
          ata(az, bx) += w * row_z[a] * row_x[b];
          ata(az, bz) += w * row_z[a] * row_z[b];
        }
      }
    }
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt = ata.ldlt();
  if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-12)) throw FitError("tangent-distance step undetermined");
  const Eigen::VectorXd x = ldlt.solve(atb);
  BSplineCurve next = c;
  for (int i = 0; i < inner; ++i) {
    next.control[static_cast<size_t>(i + 1)].x = x(2 * i);
    next.control[static_cast<size_t>(i + 1)].z = x(2 * i + 1);
  }
  return next;
}

// The standard uncertainty of the curve across itself at each point's foot, by the law of
// propagation. A point's distance along the curve's normal is linear in the control points: a_k
// for the inner ones (the rows of the tangent-distance step), e_k for the two ends, which are the
// first and last measured points and so carry their noise too. The inner ones are
// x = M (b - E ends), M = (A^T A)^-1 A^T, hence Cov(x) = s^2 (M M^T + M E E^T M^T) and
// Cov(x, ends) = -s^2 M E; u_k^2 = a_k Cov(x) a_k^T + s^2 e_k e_k^T + 2 a_k Cov(x, ends) e_k^T.
// s^2 is the points' squared distances over their degrees of freedom, m - 2 - 2 (n - 2).
std::vector<double> normal_uncertainty(const BSplineCurve& c, const std::vector<Point3>& p, const std::vector<double>& t,
                                       std::string& why_not) {
  const int count = static_cast<int>(c.control.size()), inner = count - 2;
  const int unknowns = 2 * inner;
  const int freedom = static_cast<int>(p.size()) - 2 - unknowns;
  if (inner <= 0 || freedom <= 0) {
    why_not = "no more inner points (" + std::to_string(p.size() - 2) + ") than the inner control points' coordinates (" +
              std::to_string(std::max(unknowns, 0)) + "): nothing is left to estimate the scatter from";
    return {};
  }
  const Eigen::Index m = static_cast<Eigen::Index>(p.size());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m, unknowns), e = Eigen::MatrixXd::Zero(m, 4);
  double sum_sq = 0;
  for (Eigen::Index k = 0; k < m; ++k) {
    double n[4], d1[4];
    int span = 0;
    basis_row(c.knots, count, t[static_cast<size_t>(k)], &span, n, d1);
    const Point3 d = derivative(c, t[static_cast<size_t>(k)]);
    const double length = std::hypot(d.x, d.z);
    if (!(length > 0)) {
      why_not = "the curve's tangent vanishes at point " + std::to_string(k + 1) + ", where no normal is defined";
      return {};
    }
    const double nx = -d.z / length, nz = d.x / length;
    const Point3 r = p[static_cast<size_t>(k)] - c.evaluate(t[static_cast<size_t>(k)]);
    sum_sq += r.x * r.x + r.z * r.z;
    for (int b = 0; b <= 3; ++b) {
      const int i = span - 3 + b;
      if (i == 0 || i == count - 1) {
        const int column = i == 0 ? 0 : 2;
        e(k, column) += n[b] * nx;
        e(k, column + 1) += n[b] * nz;
      } else {
        a(k, 2 * (i - 1)) = n[b] * nx;
        a(k, 2 * (i - 1) + 1) = n[b] * nz;
      }
    }
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt = (a.transpose() * a).ldlt();
  if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-12)) {
    why_not = "the points' distances along the normals do not determine the control points (their normal equations are "
              "singular: points bunched along the curve, or a curve that folds)";
    return {};
  }
  const double s2 = sum_sq / freedom;
  const Eigen::MatrixXd map = ldlt.solve(a.transpose());  // M
  const Eigen::MatrixXd map_ends = map * e;               // M E
  const Eigen::MatrixXd inner_covariance = s2 * (map * map.transpose() + map_ends * map_ends.transpose());
  const Eigen::MatrixXd cross = -s2 * map_ends;
  std::vector<double> u(p.size(), 0.0);
  for (Eigen::Index k = 0; k < m; ++k) {
    const Eigen::RowVectorXd ak = a.row(k), ek = e.row(k);
    const double variance = ak * inner_covariance * ak.transpose() + s2 * ek.squaredNorm() + 2.0 * (ak * cross * ek.transpose())(0, 0);
    u[static_cast<size_t>(k)] = std::sqrt(std::max(0.0, variance));
  }
  return u;
}

double rms_to(const BSplineCurve& c, const std::vector<Point3>& p, const std::vector<double>& t) {
  double sum = 0;
  for (size_t k = 0; k < p.size(); ++k) sum += dot(p[k] - c.evaluate(t[k]), p[k] - c.evaluate(t[k]));
  return std::sqrt(sum / static_cast<double>(p.size()));
}

}  // namespace

BSplineCurve approximate_clamped(const std::vector<Point3>& p, int control_count, ApproximationReport* report) {
  if (control_count < 4) throw FitError("a clamped cubic needs at least 4 control points");
  if (control_count > static_cast<int>(p.size())) {
    throw FitError("more control points (" + std::to_string(control_count) + ") than points (" + std::to_string(p.size()) + ")");
  }
  // Parameter correction: fit on chord-length parameters, move each inner point's parameter to its
  // foot point on the curve and improve the curve for those parameters, and repeat while the RMS of
  // the foot-point distances falls. The improvement is a tangent-distance step (above): refitting
  // by least squares on the moved parameters (Hoschek's intrinsic parameterization) converges the
  // same way but linearly, hundreds of steps on Hamdan's (2010) Table 2 boundary. The error the fit
  // reports becomes the points' orthogonal distance, not a distance at a parameter chosen before
  // the curve was known. The ends keep their parameters: the curve ends on them.
  std::vector<double> t = chord_parameters(p);
  BSplineCurve best = least_squares_clamped(p, t, control_count);
  const double chord_rms = rms_to(best, p, t);
  for (size_t k = 1; k + 1 < p.size(); ++k) t[k] = foot_parameter(best, p[k], t[k]);
  double best_rms = rms_to(best, p, t);
  int corrections = 0;
  for (int iteration = 0; iteration < 400; ++iteration) {
    BSplineCurve next;
    try {
      next = tangent_distance_step(best, p, t);
    } catch (const FitError&) {
      break;  // keep the last determined curve
    }
    std::vector<double> moved = t;
    for (size_t k = 1; k + 1 < p.size(); ++k) moved[k] = foot_parameter(next, p[k], t[k]);
    const double rms = rms_to(next, p, moved);
    // Converged fully: a curve stopped early (at a relative gain of 1e-7) is a different estimator,
    // whose spread over noisy replicas its uncertainty did not describe (36 % off).
    if (!(rms < best_rms * (1 - 1e-13))) break;
    best = std::move(next);
    best_rms = rms;
    t = std::move(moved);
    ++corrections;
  }
  if (report) {
    report->corrections = corrections;
    report->chord_rms_mm = chord_rms;
    report->corrected_rms_mm = best_rms;
    report->u_mm = normal_uncertainty(best, p, t, report->u_not_determined);
    report->u_max_mm = report->u_mean_mm = 0;
    for (double u : report->u_mm) {
      report->u_max_mm = std::max(report->u_max_mm, u);
      report->u_mean_mm += u / static_cast<double>(report->u_mm.size());
    }
  }
  return best;
}

BSplineCurve control_polygon_curve(const std::vector<Point3>& p) {
  BSplineCurve c;
  c.degree = 3;
  c.control = p;
  c.knots = clamped_uniform_knots(static_cast<int>(p.size()), 3);
  return c;
}

CeCurve curve_within_uncertainty(const std::vector<Point3>& p, double distance_mm) {
  CeCurve ce;
  const BSplineCurve first = interpolate_natural(p);
  ce.trend = fit_profile_cubic(p);
  const std::vector<double> t = chord_parameters(p);
  for (size_t k = 0; k < p.size(); ++k) {
    // The normal in the x-z plane of the interpolating curve at the point.
    const Point3 d = derivative(first, t[k]);
    Point3 normal{-d.z, 0, d.x};
    normal = (1.0 / norm(normal)) * normal;
    const Point3 a = p[k] + distance_mm * normal, b = p[k] - distance_mm * normal;
    const Point3 lower = a.z < b.z ? a : b, upper = a.z < b.z ? b : a;
    ce.offset_points.push_back(ce.trend.at(p[k].x) > p[k].z ? lower : upper);
  }
  ce.curve = interpolate_natural(ce.offset_points);
  return ce;
}

std::vector<double> curve_distances(const BSplineCurve& c, const std::vector<Point3>& points) {
  // Starts from the nearest of a dense sampling (16 per knot span), found through a bucket grid in
  // the profile's plane (x, z), then Gauss-Newton on the foot-point condition
  // (C(t) - q) . C'(t) = 0, kept within the curve.
  std::vector<double> samples;
  const std::vector<double> spans = distinct_knots(c.knots, c.t_min(), c.t_max());
  for (size_t s = 0; s + 1 < spans.size(); ++s) {
    for (int k = 0; k < 16; ++k) samples.push_back(spans[s] + (spans[s + 1] - spans[s]) * k / 16.0);
  }
  samples.push_back(c.t_max());
  std::vector<Point3> at;
  double length = 0;
  for (double t : samples) {
    at.push_back(c.evaluate(t));
    if (at.size() > 1) length += norm(at.back() - at[at.size() - 2]);
  }
  const double cell = std::max(4 * length / static_cast<double>(at.size()), 1e-9);
  auto key = [cell](double x, double z) {
    // Two's-complement bits of the cell indices side by side (shifting a negative value is undefined).
    return (static_cast<uint64_t>(static_cast<int64_t>(std::floor(x / cell))) << 32) ^
           (static_cast<uint64_t>(static_cast<int64_t>(std::floor(z / cell))) & 0xffffffffu);
  };
  std::unordered_map<uint64_t, std::vector<size_t>> buckets;
  for (size_t k = 0; k < at.size(); ++k) buckets[key(at[k].x, at[k].z)].push_back(k);
  std::vector<double> out;
  for (const Point3& q : points) {
    // Rings of cells around q until the best sample found is nearer than the ring's inner edge.
    size_t best = 0;
    double best_distance = 1e300;
    const double qx = std::floor(q.x / cell), qz = std::floor(q.z / cell);
    for (int ring = 0; ring < 1 << 20; ++ring) {
      for (int dx = -ring; dx <= ring; ++dx) {
        for (int dz = -ring; dz <= ring; ++dz) {
          if (std::abs(dx) != ring && std::abs(dz) != ring) continue;
          const auto found = buckets.find(key((qx + dx + 0.5) * cell, (qz + dz + 0.5) * cell));
          if (found == buckets.end()) continue;
          for (size_t k : found->second) {
            const double d = norm(at[k] - q);
            if (d < best_distance) {
              best_distance = d;
              best = k;
            }
          }
        }
      }
      if (best_distance <= ring * cell) break;
      if (ring > 0 && static_cast<size_t>(ring) * static_cast<size_t>(ring) > 4 * at.size() && best_distance < 1e300) break;
    }
    const double t = foot_parameter(c, q, samples[best]);
    out.push_back(norm(q - c.evaluate(t)));
  }
  return out;
}

}  // namespace dg::host
