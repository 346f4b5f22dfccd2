// Levenberg-Marquardt with a forward-difference Jacobian over eleven parameters: three sizes, two
// squareness values (kept in [0.1, 2], the range of Koivunen and Bajcsy 1992, Fig. 8), the centre and a rotation
// vector. The starts come from moments: the centroid, the principal axes of the scatter (each in
// turn as the object's z axis), and the half extents along them.
#include "host/fit/superquadric.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "host/geometry/clamp.h"
#include "host/fit/fit_error.h"
#include "host/fit/profile_curve.h"
#include "host/geometry/vec3.h"

namespace dg::host {

namespace {

constexpr int kParameters = 11;
constexpr double kMinSquareness = 0.1, kMaxSquareness = 2.0;
using Vector = Eigen::Matrix<double, kParameters, 1>;

// Parameters: a1 a2 a3 e1 e2 cx cy cz rx ry rz (rotation vector applied to the start axes).
Superquadric model_of(const Vector& x, const Eigen::Matrix3d& start_axes) {
  Superquadric s;
  for (int k = 0; k < 3; ++k) s.a[k] = x(k);
  s.e1 = x(3);
  s.e2 = x(4);
  s.center = {x(5), x(6), x(7)};
  const Eigen::Vector3d w(x(8), x(9), x(10));
  const double angle = w.norm();
  const Eigen::Matrix3d r = angle > 0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d axes = r * start_axes;  // columns: the object's axes
  for (int row = 0; row < 3; ++row) {
    for (int c = 0; c < 3; ++c) s.axes[row][c] = axes(c, row);
  }
  return s;
}

void clamp_parameters(Vector& x, double scale) {
  for (int k = 0; k < 3; ++k) x(k) = std::max(x(k), 1e-6 * scale);
  x(3) = std::clamp(x(3), kMinSquareness, kMaxSquareness);
  x(4) = std::clamp(x(4), kMinSquareness, kMaxSquareness);
}

Eigen::VectorXd residuals(const Vector& x, const Eigen::Matrix3d& start_axes, const std::vector<Point3>& points) {
  const Superquadric s = model_of(x, start_axes);
  const double volume = std::sqrt(s.a[0] * s.a[1] * s.a[2]);
  Eigen::VectorXd r(static_cast<Eigen::Index>(points.size()));
  for (size_t i = 0; i < points.size(); ++i) r(static_cast<Eigen::Index>(i)) = volume * (s.inside_outside(points[i]) - 1);
  return r;
}

bool near(double value, double target, double tolerance) { return std::fabs(value - target) <= tolerance; }

}  // namespace

double Superquadric::inside_outside(Point3 p) const {
  const Point3 d = p - center;
  double q[3];
  for (int k = 0; k < 3; ++k) q[k] = std::fabs(axes[k][0] * d.x + axes[k][1] * d.y + axes[k][2] * d.z) / a[k];
  const double xy = std::pow(q[0], 2 / e2) + std::pow(q[1], 2 / e2);
  const double f = std::pow(xy, e2 / e1) + std::pow(q[2], 2 / e1);
  return std::pow(f, e1);
}

Point3 Superquadric::surface_point(double eta, double omega) const {
  // Signed powers: x = a1 c(eta)^e1 c(omega)^e2, y = a2 c(eta)^e1 s(omega)^e2, z = a3 s(eta)^e1.
  auto spow = [](double v, double e) { return std::copysign(std::pow(std::fabs(v), e), v); };
  const double local[3] = {a[0] * spow(std::cos(eta), e1) * spow(std::cos(omega), e2),
                           a[1] * spow(std::cos(eta), e1) * spow(std::sin(omega), e2), a[2] * spow(std::sin(eta), e1)};
  Point3 p = center;
  for (int k = 0; k < 3; ++k) p += local[k] * Point3{axes[k][0], axes[k][1], axes[k][2]};
  return p;
}

const char* shape_name(SuperquadricShape shape) {
  switch (shape) {
    case SuperquadricShape::kEllipsoid: return "ellipsoid";
    case SuperquadricShape::kCylinder: return "cylinder";
    case SuperquadricShape::kParallelepiped: return "parallelepiped";
    case SuperquadricShape::kRotational: return "solid of revolution";
    case SuperquadricShape::kOther: return "other";
  }
  return "other";
}

namespace {

// Forward differences of the residuals r = residuals(x) in each parameter.
Eigen::MatrixXd jacobian_at(const Vector& x, const Eigen::VectorXd& r, const Eigen::Matrix3d& start_axes,
                            const std::vector<Point3>& points, double scale) {
  Eigen::MatrixXd jacobian(r.size(), kParameters);
  for (int k = 0; k < kParameters; ++k) {
    Vector step = x;
    const double h = (k < 3 || (k >= 5 && k < 8) ? 1e-7 * scale : 1e-7) * (1 + std::fabs(x(k)));
    step(k) += h;
    jacobian.col(k) = (residuals(step, start_axes, points) - r) / h;
  }
  return jacobian;
}

// Standard uncertainties of the sizes, exponents and centre at the solution (GUM's law of
// propagation for a least-squares estimate), with the scatter of the points about the fitted
// shape as the measure of their noise. Directions the points do not determine (the turn of a
// sphere) are left out of the pseudo-inverse; they do not move the sizes or the centre.
SuperquadricUncertainty parameter_uncertainty(const Vector& x, const Eigen::Matrix3d& axes, const std::vector<Point3>& points,
                                              double scale) {
  SuperquadricUncertainty u;
  const Eigen::Index m = static_cast<Eigen::Index>(points.size());
  if (m <= kParameters) return u;
  const Eigen::VectorXd r = residuals(x, axes, points);
  const Eigen::MatrixXd j = jacobian_at(x, r, axes, points, scale);
  const Eigen::Matrix<double, kParameters, kParameters> jtj = j.transpose() * j;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, kParameters, kParameters>> eigen(jtj);
  if (eigen.info() != Eigen::Success) return u;
  const double largest = eigen.eigenvalues().maxCoeff();
  if (!(largest > 0)) return u;
  Eigen::Matrix<double, kParameters, kParameters> inverse = Eigen::Matrix<double, kParameters, kParameters>::Zero();
  for (int k = 0; k < kParameters; ++k) {
    const double value = eigen.eigenvalues()(k);
    if (value > 1e-12 * largest) inverse += eigen.eigenvectors().col(k) * eigen.eigenvectors().col(k).transpose() / value;
  }
  // The residuals are of the inside-outside function, whose noise grows and shrinks over the
  // shape with its slope: their variance differs from point to point, so the covariance is the
  // heteroscedasticity-consistent sandwich A^+ (sum r_i^2 J_i^T J_i) A^+ (with m / (m - 11)), not
  // s^2 A^+ (which was up to 36 % off the Monte Carlo spread).
  Eigen::Matrix<double, kParameters, kParameters> meat = Eigen::Matrix<double, kParameters, kParameters>::Zero();
  for (Eigen::Index i = 0; i < m; ++i) meat += r(i) * r(i) * j.row(i).transpose() * j.row(i);
  const Eigen::Matrix<double, kParameters, kParameters> covariance =
      inverse * meat * inverse * (static_cast<double>(m) / static_cast<double>(m - kParameters));
  auto standard = [&](int k) { return std::sqrt(std::max(0.0, covariance(k, k))); };
  for (int k = 0; k < 3; ++k) u.a_mm[k] = standard(k);
  u.e1 = standard(3);
  u.e2 = standard(4);
  for (int k = 0; k < 3; ++k) u.center_mm[k] = standard(5 + k);
  u.computed = std::isfinite(u.a_mm[0] + u.a_mm[1] + u.a_mm[2] + u.e1 + u.e2 + u.center_mm[0] + u.center_mm[1] + u.center_mm[2]);
  return u;
}

// Levenberg-Marquardt from x on `points`; returns the iterations taken and leaves the cost.
int levenberg_marquardt(Vector& x, const Eigen::Matrix3d& start_axes, const std::vector<Point3>& points, double scale,
                        int max_iterations, double* final_cost) {
  int iterations = 0;
  Eigen::VectorXd r = residuals(x, start_axes, points);
  double cost = r.squaredNorm();
  double lambda = 1e-3;
  bool converged = false;
  for (iterations = 0; iterations < max_iterations && !converged; ++iterations) {
    const Eigen::MatrixXd jacobian = jacobian_at(x, r, start_axes, points, scale);
    const Eigen::Matrix<double, kParameters, kParameters> jtj = jacobian.transpose() * jacobian;
    const Vector jtr = jacobian.transpose() * r;
    bool improved = false;
    for (int attempt = 0; attempt < 12 && !improved; ++attempt) {
      Eigen::Matrix<double, kParameters, kParameters> damped = jtj;
      for (int k = 0; k < kParameters; ++k) damped(k, k) += lambda * std::max(jtj(k, k), 1e-12);
      Vector candidate = x - damped.ldlt().solve(jtr);
      clamp_parameters(candidate, scale);
      const Eigen::VectorXd r_candidate = residuals(candidate, start_axes, points);
      const double candidate_cost = r_candidate.squaredNorm();
      if (std::isfinite(candidate_cost) && candidate_cost < cost) {
        const double gain = cost - candidate_cost;
        // Sizes and the centre in units of the part, the rest as they are.
        Vector change = candidate - x;
        for (int k : {0, 1, 2, 5, 6, 7}) change(k) /= scale;
        const bool settled = change.norm() < 1e-9;
        x = candidate;
        r = r_candidate;
        cost = candidate_cost;
        lambda = std::max(lambda / 10, 1e-12);
        improved = true;
        converged = settled || gain <= 1e-10 * cost + 1e-300;
      } else {
        lambda *= 10;
      }
    }
    if (!improved) break;
  }
  *final_cost = cost;
  return iterations;
}

}  // namespace

SuperquadricFit fit_superquadric(const std::vector<Point3>& points, const SuperquadricOptions& options) {
  if (points.size() < kParameters) {
    throw FitError("a superquadric has 11 parameters and needs at least 11 points; got " + std::to_string(points.size()));
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Point3& p : points) {
    if (!std::isfinite(p.x + p.y + p.z)) throw FitError("a point is not finite");
    mean += Eigen::Vector3d(p.x, p.y, p.z);
  }
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Point3& p : points) {
    const Eigen::Vector3d d = Eigen::Vector3d(p.x, p.y, p.z) - mean;
    scatter += d * d.transpose();
  }
  scatter /= static_cast<double>(points.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  const Eigen::Vector3d spread = eigen.eigenvalues();  // ascending
  const double scale = std::sqrt(spread(2));
  if (!(spread(0) > 1e-6 * spread(2)) || !(scale > 0)) {
    throw FitError("the points lie in a plane or on a line (spread " + std::to_string(std::sqrt(std::max(spread(0), 0.0))) +
                   " mm across it): a superquadric needs points with volume");
  }
  // Starts: each principal direction in turn as the object's z axis (the moments cannot tell which
  // one the shape's exponents belong to: a 40 x 25 x 12 shape may have its e1 about any of them),
  // and across it the other two principal directions. Where their spreads are within 10 % of each
  // other the moments fix no direction across the axis, and a cross-section fitted turned away from
  // the true one settles in a false minimum (a rounded square turned 45 degrees looks like a
  // rounded diamond, e2 near 2 - e2): there four turns 22.5 degrees apart are tried. Each start runs
  // for at most 100 iterations on a sample of at most 600 points; the best two are refined on all
  // of them (at most 20,000 for most iterations on large scans: each iteration evaluates every
  // point twelve times).
  auto strided = [&points](size_t count) {
    if (points.size() <= count) return points;
    std::vector<Point3> sample;
    const double stride = static_cast<double>(points.size()) / static_cast<double>(count);
    for (size_t k = 0; k < count; ++k) sample.push_back(points[static_cast<size_t>(static_cast<double>(k) * stride)]);
    return sample;
  };
  const std::vector<Point3> trial_points = strided(600);
  struct Trial {
    double cost;
    Vector x;
    Eigen::Matrix3d axes;
  };
  std::vector<Trial> trials;
  SuperquadricFit fit;
  for (int z_axis = 0; z_axis < 3; ++z_axis) {
    const double spread_a = spread((z_axis + 1) % 3), spread_b = spread((z_axis + 2) % 3);
    const bool round_across = std::fabs(spread_a - spread_b) <= 0.1 * std::max(spread_a, spread_b);
    std::vector<double> turns = {0.0};
    if (round_across) turns = {0.0, M_PI / 8, M_PI / 4, 3 * M_PI / 8};
    for (double turn : turns) {
      Eigen::Matrix3d axes;
      axes.col(2) = eigen.eigenvectors().col(z_axis);
      const Eigen::Vector3d across = eigen.eigenvectors().col((z_axis + 1) % 3);
      axes.col(0) = std::cos(turn) * across + std::sin(turn) * axes.col(2).cross(across);
      axes.col(1) = axes.col(2).cross(axes.col(0));
      Vector start = Vector::Zero();
      for (const Point3& p : points) {
        const Eigen::Vector3d d = Eigen::Vector3d(p.x, p.y, p.z) - mean;
        for (int k = 0; k < 3; ++k) start(k) = std::max(start(k), std::fabs(axes.col(k).dot(d)));
      }
      start(3) = start(4) = 1;
      start(5) = mean(0);
      start(6) = mean(1);
      start(7) = mean(2);
      double cost = 0;
      fit.iterations += levenberg_marquardt(start, axes, trial_points, scale, std::min(options.max_iterations, 100), &cost);
      trials.push_back({cost, start, axes});
    }
  }
  // The two best trials are refined: shapes near a symmetry (a rounded diamond, e2 near 2, is
  // nearly a rounded square turned 45 degrees, e2 near 0.1) leave two minima within a sample's
  // noise of each other, and only all the points tell them apart.
  std::sort(trials.begin(), trials.end(), [](const Trial& a, const Trial& b) { return a.cost < b.cost; });
  constexpr size_t kSample = 20000;
  Vector x = trials[0].x;
  Eigen::Matrix3d start_axes = trials[0].axes;
  double cost = HUGE_VAL;
  for (size_t k = 0; k < std::min<size_t>(2, trials.size()); ++k) {
    Vector candidate = trials[k].x;
    double candidate_cost = trials[k].cost;
    if (points.size() > 2 * kSample) {
      fit.iterations += levenberg_marquardt(candidate, trials[k].axes, strided(kSample), scale, options.max_iterations, &candidate_cost);
      fit.iterations += levenberg_marquardt(candidate, trials[k].axes, points, scale, 10, &candidate_cost);
    } else {
      fit.iterations += levenberg_marquardt(candidate, trials[k].axes, points, scale, options.max_iterations, &candidate_cost);
    }
    if (candidate_cost < cost) {
      cost = candidate_cost;
      x = candidate;
      start_axes = trials[k].axes;
    }
  }
  fit.model = model_of(x, start_axes);
  fit.uncertainty = parameter_uncertainty(x, start_axes, points.size() > kSample ? strided(kSample) : points, scale);
  if (points.size() > kSample) {
    // On a strided sample the scatter is the same but the points fewer: scale to all of them.
    const double shrink = std::sqrt(static_cast<double>(kSample) / static_cast<double>(points.size()));
    for (double& v : fit.uncertainty.a_mm) v *= shrink;
    for (double& v : fit.uncertainty.center_mm) v *= shrink;
    fit.uncertainty.e1 *= shrink;
    fit.uncertainty.e2 *= shrink;
  }
  fit.objective = cost;
  fit.goodness = cost / static_cast<double>(points.size());
  double radial = 0;
  for (const Point3& p : points) {
    const double f = fit.model.inside_outside(p);
    // f (eq. 9) grows as the (2 / e1)-th power along a ray from the centre, so F = f^e1 as its
    // square: the surface point on the ray through p is p / sqrt(F).
    const double d = norm(p - fit.model.center) * std::fabs(1 - 1 / std::sqrt(f));
    radial += d * d;
  }
  fit.rms_radial_mm = std::sqrt(radial / static_cast<double>(points.size()));

  // Koivunen and Bajcsy's (1992) classes: e2 ~ 1 with equal a1, a2 is symmetric about z; e1 ~ 0.1 makes it a
  // cylinder, e1 ~ 1 an ellipsoid; e1 ~ 0.1 with e2 ~ 0.1 or ~ 2 a parallelepiped.
  const Superquadric& m = fit.model;
  const double d = options.shape_tolerance;
  const bool round = near(m.e2, 1.0, d) && std::fabs(m.a[0] - m.a[1]) <= options.size_tolerance * std::max(m.a[0], m.a[1]);
  fit.rotationally_symmetric = round;
  if (near(m.e1, 0.1, d) && (near(m.e2, 0.1, d) || near(m.e2, 2.0, d))) fit.shape = SuperquadricShape::kParallelepiped;
  else if (round && near(m.e1, 0.1, d)) fit.shape = SuperquadricShape::kCylinder;
  else if (near(m.e1, 1.0, d) && near(m.e2, 1.0, d)) fit.shape = SuperquadricShape::kEllipsoid;
  else if (round) fit.shape = SuperquadricShape::kRotational;
  fit.description = shape_name(fit.shape);
  if (round) {
    char text[160];
    std::snprintf(text, sizeof text, ", symmetric about the axis through (%.3f, %.3f, %.3f) along (%.4f, %.4f, %.4f)",
                  m.center.x, m.center.y, m.center.z, m.axes[2][0], m.axes[2][1], m.axes[2][2]);
    fit.description += text;
  }
  return fit;
}

namespace {

// One pass: slices across `axis` through `c`, a circle in each, the line through their centres.
RevolutionFit slice_circles(const std::vector<Point3>& points, const Eigen::Vector3d& c, Eigen::Vector3d axis, int slice_count) {
  axis.normalize();
  Eigen::Vector3d e1 = axis.unitOrthogonal();
  const Eigen::Vector3d e2 = axis.cross(e1);
  double lo = 1e300, hi = -1e300;
  for (const Point3& p : points) {
    const double s = axis.dot(Eigen::Vector3d(p.x, p.y, p.z) - c);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  RevolutionFit fit;
  double sum_squares = 0;
  size_t used = 0;
  Eigen::MatrixXd centres(0, 3);
  for (int k = 0; k < slice_count; ++k) {
    const double a = lo + (hi - lo) * k / slice_count, b = lo + (hi - lo) * (k + 1) / slice_count;
    // Direct least squares circle (x^2 + y^2 + D x + E y + F = 0) in the slice's plane.
    Eigen::MatrixXd m(0, 3);
    Eigen::VectorXd rhs(0);
    std::vector<Eigen::Vector2d> in_plane;
    double s_sum = 0;
    for (const Point3& p : points) {
      const Eigen::Vector3d d = Eigen::Vector3d(p.x, p.y, p.z) - c;
      const double s = axis.dot(d);
      if (s < a || (s >= b && k + 1 < slice_count) || s > b) continue;
      in_plane.emplace_back(e1.dot(d), e2.dot(d));
      s_sum += s;
    }
    if (in_plane.size() < 8) continue;
    m.resize(static_cast<Eigen::Index>(in_plane.size()), 3);
    rhs.resize(static_cast<Eigen::Index>(in_plane.size()));
    for (size_t i = 0; i < in_plane.size(); ++i) {
      const Eigen::Vector2d q = in_plane[i];
      m.row(static_cast<Eigen::Index>(i)) << q(0), q(1), 1.0;
      rhs(static_cast<Eigen::Index>(i)) = -q.squaredNorm();
    }
    const Eigen::Vector3d def = m.colPivHouseholderQr().solve(rhs);
    const Eigen::Vector2d centre(-def(0) / 2, -def(1) / 2);
    const double radius = std::sqrt(std::max(centre.squaredNorm() - def(2), 0.0));
    RevolutionSlice slice;
    slice.s_mm = s_sum / static_cast<double>(in_plane.size());
    const Eigen::Vector3d at = c + slice.s_mm * axis + centre(0) * e1 + centre(1) * e2;
    slice.center = {at(0), at(1), at(2)};
    slice.radius_mm = radius;
    slice.points = in_plane.size();
    double slice_squares = 0;
    for (const Eigen::Vector2d& q : in_plane) {
      const double e = (q - centre).norm() - radius;
      slice_squares += e * e;
    }
    slice.rms_mm = std::sqrt(slice_squares / static_cast<double>(in_plane.size()));
    sum_squares += slice_squares;
    used += in_plane.size();
    fit.slices.push_back(slice);
    centres.conservativeResize(centres.rows() + 1, 3);
    centres.row(centres.rows() - 1) = at.transpose();
  }
  if (fit.slices.size() < 2) throw FitError("too few points in slices across the axis to check a rotational symmetry");
  // The axis: the line through the slice centres (their principal direction).
  const Eigen::RowVector3d mean = centres.colwise().mean();
  const Eigen::MatrixXd centred = centres.rowwise() - mean;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(centred, Eigen::ComputeThinV);
  Eigen::Vector3d direction = svd.matrixV().col(0);
  if (direction.dot(axis) < 0) direction = -direction;
  fit.axis_point = {mean(0), mean(1), mean(2)};
  fit.axis_direction = {direction(0), direction(1), direction(2)};
  fit.rms_mm = std::sqrt(sum_squares / static_cast<double>(used));
  return fit;
}

}  // namespace

RevolutionFit fit_revolution(const std::vector<Point3>& points, const Superquadric& model, int slice_count) {
  // The superquadric's axis is coarse (Koivunen and Bajcsy 1992 says so): slices across a tilted axis cut
  // ellipses, so slice again across the axis the circles found until it stops moving.
  Eigen::Vector3d c(model.center.x, model.center.y, model.center.z);
  Eigen::Vector3d axis(model.axes[2][0], model.axes[2][1], model.axes[2][2]);
  RevolutionFit fit;
  for (int pass = 0; pass < 20; ++pass) {
    fit = slice_circles(points, c, axis, slice_count);
    const Eigen::Vector3d refined(fit.axis_direction.x, fit.axis_direction.y, fit.axis_direction.z);
    const double moved = (refined - axis.normalized()).norm();
    axis = refined;
    c = Eigen::Vector3d(fit.axis_point.x, fit.axis_point.y, fit.axis_point.z);
    if (moved < 1e-12) break;
  }
  return fit;
}

BSplineSurface revolution_surface(const RevolutionFit& fit, int angular_controls) {
  if (fit.slices.size() < 2) throw FitError("a surface of revolution needs at least 2 slice circles");
  // The profile: (position along the axis, radius) as the x and z of a planar curve.
  std::vector<RevolutionSlice> slices = fit.slices;
  std::sort(slices.begin(), slices.end(), [](const RevolutionSlice& a, const RevolutionSlice& b) { return a.s_mm < b.s_mm; });
  const Point3 d = fit.axis_direction;
  std::vector<Point3> profile;
  for (const RevolutionSlice& slice : slices) {
    // The slice centre's position along the refined axis (its s_mm was along the first guess).
    profile.push_back({dot(slice.center - fit.axis_point, d), 0, slice.radius_mm});
  }
  BSplineCurve curve;
  if (profile.size() >= 3) {
    curve = interpolate_natural(profile);
  } else {
    curve.degree = 1;
    curve.control = profile;
    curve.knots = {0, 0, 1, 1};
  }
  // The circle: control points at radius rho so that the knot points (P[k-1] + 4 P[k] + P[k+1]) / 6
  // lie on the unit circle; three repeated at the end close it.
  const int n = std::max(angular_controls, 8);
  const double rho = 6 / (4 + 2 * std::cos(2 * M_PI / n));
  Point3 e1 = cross(d, Point3{1, 0, 0});
  if (norm(e1) < 0.5) e1 = cross(d, Point3{0, 1, 0});
  e1 = (1.0 / norm(e1)) * e1;
  const Point3 e2 = cross(d, e1);
  std::vector<Point3> circle;
  for (int k = 0; k < n + 3; ++k) {
    const double a = 2 * M_PI * (k % n) / n;
    circle.push_back(rho * (std::cos(a) * e1 + std::sin(a) * e2));
  }
  BSplineSurface s;
  s.degree_u = curve.degree;
  s.degree_v = 3;
  s.count_u = static_cast<int>(curve.control.size());
  s.count_v = n + 3;
  s.knots_u = curve.knots;
  for (int k = 0; k < n + 7; ++k) s.knots_v.push_back(static_cast<double>(k - 3) / n);
  for (const Point3& c : curve.control) {
    // x along the axis, z the radius: the control point's ring.
    for (const Point3& q : circle) s.control.push_back(fit.axis_point + c.x * d + c.z * q);
  }
  return clamp_ends(s);
}

}  // namespace dg::host
