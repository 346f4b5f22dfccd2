// ICP with point-to-plane residuals, solved by Eigen.
#include "host/fit/rigid_align.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "host/geometry/vec3.h"

namespace dg::host {

Point3 RigidTransform::apply(const Point3& p) const {
  const auto& r = rotation;
  return {r[0][0] * p.x + r[0][1] * p.y + r[0][2] * p.z + translation.x,
          r[1][0] * p.x + r[1][1] * p.y + r[1][2] * p.z + translation.y,
          r[2][0] * p.x + r[2][1] * p.y + r[2][2] * p.z + translation.z};
}

double RigidTransform::angle_deg() const {
  const double trace = rotation[0][0] + rotation[1][1] + rotation[2][2];
  return std::acos(std::clamp((trace - 1) / 2, -1.0, 1.0)) * 180.0 / M_PI;
}

namespace {

// The least a freedom's moving by 1 mm (a turn by 1 radian at the points' RMS radius) changes the
// points' mean squared distance by, in mm^2 per mm^2: below it the nominal's shape does not fix
// that freedom (a datum must; a best fit holds it still).
constexpr double kMinSensitivity = 1e-4;

// The |distances| of the points over the nominal, moved by t: those beyond its edge are left out.
std::vector<double> distances_over(const std::vector<Point3>& points, const RigidTransform& t,
                                   const std::function<Closest(const Point3&)>& closest) {
  std::vector<double> over;
  for (const Point3& p : points) {
    const Point3 moved = t.apply(p);
    const Closest c = closest(moved);
    if (!beyond_edge(moved, c)) over.push_back(std::fabs(c.distance));
  }
  return over;
}

// The RMS distance of the points over the nominal, moved by t; the ones beyond its edge are
// counted into `beyond` when given.
double rms_of(const std::vector<Point3>& points, const RigidTransform& t, const std::function<Closest(const Point3&)>& closest,
              size_t* beyond = nullptr) {
  const std::vector<double> over = distances_over(points, t, closest);
  double sum = 0;
  for (double d : over) sum += d * d;
  if (beyond) *beyond = points.size() - over.size();
  return std::sqrt(sum / static_cast<double>(std::max<size_t>(1, over.size())));
}

// The trimmed cost of an alignment: the mean of the smallest 90 % of the squared distances. Trimmed
// ICP need not lower it at every step (its points in and out change), so the best transform seen
// by this one measure is the one kept.
double trimmed_cost(std::vector<double> distances) {
  if (distances.empty()) return 0;
  for (double& d : distances) d *= d;
  const size_t keep = std::max<size_t>(1, distances.size() * 9 / 10);
  std::nth_element(distances.begin(), distances.begin() + static_cast<std::ptrdiff_t>(keep - 1), distances.end());
  double sum = 0;
  for (size_t k = 0; k < keep; ++k) sum += distances[k];
  return sum / static_cast<double>(keep);
}

// ICP steps from `start` moving only the freedoms in `free`; the points' sensitivities to them
// (the normal matrix over the points taking part, rotations scaled by their RMS radius) left in
// `sensitivity` for a caller that must know each freedom is determined.
Alignment align_steps(const std::vector<Point3>& all, const std::function<Closest(const Point3&)>& closest, size_t max_points,
                      const RigidTransform& start, const FreedomMask& free, Eigen::Matrix<double, 6, 6>* sensitivity) {
  std::vector<Point3> points;
  const size_t stride = std::max<size_t>(1, all.size() / std::max<size_t>(1, max_points));
  for (size_t k = 0; k < all.size(); k += stride) points.push_back(all[k]);
  Alignment out;
  out.transform = start;
  // Rotations about the points' centroid keep the linear system well conditioned.
  Point3 centroid;
  for (const Point3& p : points) centroid += start.apply(p);
  centroid = (1.0 / static_cast<double>(std::max<size_t>(1, points.size()))) * centroid;
  double radius2 = 0;
  for (const Point3& p : points) radius2 += dot(start.apply(p) - centroid, start.apply(p) - centroid);
  const double radius = std::sqrt(radius2 / static_cast<double>(std::max<size_t>(1, points.size())));
  out.rms_before_mm = rms_of(points, out.transform, closest);
  Eigen::Matrix3d rotation;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rotation(i, j) = start.rotation[i][j];
  Eigen::Vector3d translation(start.translation.x, start.translation.y, start.translation.z);
  RigidTransform best = start;
  double best_cost = HUGE_VAL;
  int free_count = 0;
  for (bool f : free) free_count += f;
  for (int iteration = 1; iteration <= 50; ++iteration) {
    Eigen::Matrix<double, 6, 6> normal = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
    // A trimmed fit: points farther than 3 robust sigmas (1.4826 x the median |distance| of the
    // points over the nominal) are left out of this step, so that outliers and unscanned features
    // cannot pull it; so are the points beyond the nominal's edge (Turk and Levoy 1994), whose
    // distance to the edge would pull the part towards it.
    std::vector<Point3> moved_points;
    std::vector<Closest> feet;
    std::vector<double> distances, over;
    std::vector<char> beyond;
    for (const Point3& p : points) {
      moved_points.push_back(out.transform.apply(p));
      feet.push_back(closest(moved_points.back()));
      distances.push_back(std::fabs(feet.back().distance));
      beyond.push_back(beyond_edge(moved_points.back(), feet.back()));
      if (!beyond.back()) over.push_back(distances.back());
    }
    out.beyond_edge = points.size() - over.size();
    if (over.empty()) {
      throw std::invalid_argument("every one of the " + std::to_string(points.size()) +
                                  " points aligned lies beyond the nominal's edge, so none can be fitted to it along a normal: "
                                  "are they the points of this part, in its coordinates?");
    }
    const double cost = trimmed_cost(over);
    if (cost < best_cost) best_cost = cost, best = out.transform;
    std::vector<double> sorted = over;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    // Never below 1 nm: the closest points themselves settle to 1e-7 mm.
    const double cutoff = std::max(3 * 1.4826 * sorted[sorted.size() / 2], 1e-6);
    out.left_out = 0;
    size_t used = 0;
    for (size_t k = 0; k < points.size(); ++k) {
      const Point3& moved = moved_points[k];
      const Closest& c = feet[k];
      if (beyond[k]) continue;
      if (distances[k] > cutoff) {
        ++out.left_out;
        continue;
      }
      // The nominal's normal at the foot: the tangent plane the point may slide along.
      const Point3 n = c.normal;
      if (!(norm(n) > 0)) continue;
      const double residual = dot(moved - c.point, n);
      const Point3 arm = moved - centroid;
      const Point3 a = cross(arm, n);
      Eigen::Matrix<double, 6, 1> row;
      row << a.x, a.y, a.z, n.x, n.y, n.z;
      for (int f = 0; f < 6; ++f) row(f) = free[static_cast<size_t>(f)] ? row(f) : 0.0;
      normal += row * row.transpose();
      rhs -= row * residual;
      ++used;
    }
    // Rotations in radians times the points' RMS radius: a distance, as translations are; per point.
    const Eigen::Matrix<double, 6, 1> scale = (Eigen::Matrix<double, 6, 1>() << 1 / std::max(radius, 1e-12),
                                               1 / std::max(radius, 1e-12), 1 / std::max(radius, 1e-12), 1, 1, 1).finished();
    const double per_point = 1.0 / static_cast<double>(std::max<size_t>(1, used));
    const Eigen::Matrix<double, 6, 6> scaled = scale.asDiagonal() * normal * scale.asDiagonal() * per_point;
    if (sensitivity) *sensitivity = scaled;
    // A plane lets the points slide along it, a cylinder turn about its axis and a sphere about its
    // centre without changing a distance: the step is solved only along the directions the shape
    // fixes (kMinSensitivity), and held still along the others, which noise and the fit's small
    // departures from the shape would otherwise move at random (a sphere's patch turned 3 degrees).
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(scaled);
    const Eigen::Matrix<double, 6, 1> projected = eigen.eigenvectors().transpose() * (scale.asDiagonal() * rhs * per_point);
    Eigen::Matrix<double, 6, 1> solved = Eigen::Matrix<double, 6, 1>::Zero();
    int determined = 0;
    for (int i = 0; i < 6; ++i) {
      if (!(eigen.eigenvalues()(i) >= kMinSensitivity)) continue;
      solved(i) = projected(i) / eigen.eigenvalues()(i);
      ++determined;
    }
    out.held = std::max(0, free_count - determined);
    const Eigen::Matrix<double, 6, 1> step = scale.asDiagonal() * (eigen.eigenvectors() * solved);
    if (!step.allFinite()) break;
    // The small rotation as an exact one (Rodrigues), about the centroid.
    const Eigen::Vector3d omega = step.head<3>();
    const double angle = omega.norm();
    const Eigen::Matrix3d delta = angle > 0 ? Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
    const Eigen::Vector3d c(centroid.x, centroid.y, centroid.z);
    rotation = delta * rotation;
    translation = delta * (translation - c) + c + step.tail<3>();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) out.transform.rotation[i][j] = rotation(i, j);
    out.transform.translation = {translation.x(), translation.y(), translation.z()};
    out.iterations = iteration;
    // The largest move of a point: the rotation's arm times its angle, plus the translation.
    double reach = 0;
    for (const Point3& p : points) reach = std::max(reach, norm(start.apply(p) - centroid));
    if (angle * reach + step.tail<3>().norm() < 1e-7) {
      out.converged = true;
      break;
    }
  }
  // The last transform against the best seen before it (every step saw points over the nominal, so
  // there is one).
  const std::vector<double> last = distances_over(points, out.transform, closest);
  if (!out.converged && (last.empty() || trimmed_cost(last) > best_cost)) out.transform = best;
  out.rms_after_mm = rms_of(points, out.transform, closest, &out.beyond_edge);
  return out;
}

}  // namespace

Alignment align_to_nominal(const std::vector<Point3>& all, const std::function<Closest(const Point3&)>& closest, size_t max_points) {
  return align_steps(all, closest, max_points, RigidTransform{}, FreedomMask{true, true, true, true, true, true}, nullptr);
}

Alignment align_to_datums(std::vector<DatumFit>& datums, const std::function<Closest(const Point3&)>& closest) {
  if (datums.empty() || datums.size() > 3) throw std::invalid_argument("a datum alignment takes one, two or three datums");
  static const char* const kFreedom[6] = {"tilt about x", "tilt about y", "rotation about z", "x", "y", "height (z)"};
  const size_t n = datums.size();
  datums[0].fixes = {true, true, false, false, false, true};
  datums[0].fixes_text = "tilt about x and y, height";
  if (n >= 2) {
    datums[1].fixes = n == 2 ? FreedomMask{false, false, true, true, true, false} : FreedomMask{false, false, true, true, false, false};
    datums[1].fixes_text = n == 2 ? "rotation about z, x and y" : "rotation about z, x";
  }
  if (n == 3) {
    datums[2].fixes = {false, false, false, false, true, false};
    datums[2].fixes_text = "y";
  }
  Alignment out;
  out.converged = true;
  std::vector<Point3> together;
  for (const DatumFit& d : datums) together.insert(together.end(), d.points.begin(), d.points.end());
  for (DatumFit& d : datums) {
    if (d.points.empty()) throw std::invalid_argument("datum " + d.name + " holds none of the points: is its box in the scan's coordinates?");
    Eigen::Matrix<double, 6, 6> sensitivity;
    const Alignment step = align_steps(d.points, closest, 20000, out.transform, d.fixes, &sensitivity);
    // Each freedom the datum fixes must be determined by it, and not only together with another:
    // the smallest eigenvalue of its freedoms' block, and each freedom's own diagonal.
    std::vector<int> fixed;
    for (int f = 0; f < 6; ++f)
      if (d.fixes[static_cast<size_t>(f)]) fixed.push_back(f);
    Eigen::MatrixXd block(fixed.size(), fixed.size());
    for (size_t i = 0; i < fixed.size(); ++i)
      for (size_t j = 0; j < fixed.size(); ++j) block(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = sensitivity(fixed[i], fixed[j]);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(block);
    if (eigen.eigenvalues().minCoeff() < kMinSensitivity) {
      // Name the freedom the weakest direction leans on most.
      Eigen::Index weakest = 0;
      eigen.eigenvectors().col(0).cwiseAbs().maxCoeff(&weakest);
      throw std::invalid_argument("datum " + d.name + " cannot fix the " + kFreedom[fixed[static_cast<size_t>(weakest)]] +
                                  ": moving the part that way hardly changes its points' distances to the nominal (a datum "
                                  "fixes x or y only where it slopes along them, by more than about 0.6 degrees, and no turn "
                                  "about z where it is round about a vertical axis); name another region, or fewer datums");
    }
    d.used = std::min(d.points.size(), static_cast<size_t>(20000));
    out.transform = step.transform;
    out.iterations += step.iterations;
    out.left_out += step.left_out;
    out.converged = out.converged && step.converged;
  }
  // Each datum's RMS, and all of theirs together, before and once every datum has moved the part.
  // A datum whose points the later ones carried all beyond the nominal's edge has no RMS to give.
  for (DatumFit& d : datums) {
    size_t beyond = 0;
    d.rms_after_mm = rms_of(d.points, out.transform, closest, &beyond);
    if (beyond == d.points.size()) {
      throw std::invalid_argument("datum " + d.name + ": every one of its points lies beyond the nominal's edge once the part is "
                                  "aligned, so none has a distance to it along a normal: is its box on the part the nominal "
                                  "covers?");
    }
  }
  out.rms_before_mm = rms_of(together, RigidTransform{}, closest);
  out.rms_after_mm = rms_of(together, out.transform, closest, &out.beyond_edge);
  return out;
}

Alignment align_to_surface(const std::vector<Point3>& points, const SurfaceLocator& nominal, size_t max_points) {
  return align_to_nominal(points, [&](const Point3& p) { return nominal.closest(p); }, max_points);
}

}  // namespace dg::host
