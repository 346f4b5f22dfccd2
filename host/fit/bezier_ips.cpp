// Hamdan's (2010) inverse progressive search for bicubic Bezier patches, with orthogonal distances as
// the error of eq. 11-12 and a search that narrows around its best point instead of stopping at the
// first candidate below an error limit (which would need the limit in advance).
#include "host/fit/bezier_ips.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "common/fit/bernstein.h"
#include "host/geometry/closest_point.h"
#include "host/fit/fit_error.h"
#include "host/geometry/vec3.h"

namespace dg::host {

Point3 CubicBezierCurve::at(double t) const {
  double b[4];
  fit::bernstein(3, t, b);
  return b[0] * p[0] + b[1] * p[1] + b[2] * p[2] + b[3] * p[3];
}

Point3 CubicBezierCurve::derivative(double t) const {
  double b[4];
  fit::bernstein_derivative(3, t, b);
  return b[0] * p[0] + b[1] * p[1] + b[2] * p[2] + b[3] * p[3];
}

Point3 CubicBezierCurve::second_derivative(double t) const {
  // The derivative of a cubic's derivative: 6 times the linear Bezier of second differences.
  const Point3 d0 = p[2] - 2.0 * p[1] + p[0], d1 = p[3] - 2.0 * p[2] + p[1];
  return 6.0 * ((1 - t) * d0 + t * d1);
}

double closest_parameter(const CubicBezierCurve& curve, const Point3& q, double t0) {
  double t = std::clamp(t0, 0.0, 1.0);
  for (int iteration = 0; iteration < 30; ++iteration) {
    const Point3 r = curve.at(t) - q, d = curve.derivative(t);
    const double f = dot(r, d);
    double slope = dot(d, d) + dot(r, curve.second_derivative(t));
    // Away from the minimum the full Newton slope can vanish or turn negative; the Gauss-Newton
    // slope |C'|^2 still points downhill.
    if (!(slope > 0)) slope = dot(d, d);
    if (!(slope > 0)) break;
    const double next = std::clamp(t - f / slope, 0.0, 1.0);
    const bool settled = std::abs(next - t) < 1e-13;
    t = next;
    if (settled) break;
  }
  return t;
}

bool tangent_intersection(const Point3& a, const Point3& b, const Point3& c, const Point3& d, Point3& meet) {
  // Lines a + s (b - a) and c + t (d - c): the closest approach solves a 2 x 2 system.
  const Point3 e = b - a, f = d - c, w = a - c;
  const double ee = dot(e, e), ef = dot(e, f), ff = dot(f, f), ew = dot(e, w), fw = dot(f, w);
  const double det = ee * ff - ef * ef;
  if (!(det > 1e-12 * ee * ff)) return false;
  const double s = (ef * fw - ff * ew) / det, t = (ee * fw - ef * ew) / det;
  meet = 0.5 * ((a + s * e) + (c + t * f));
  return true;
}

namespace {

// The tangent at the first of `points` (taken from the back when `from_end`), pointing into the
// curve. Hamdan 2010 draws it through the first two points; with a gauge's few micrometres of noise on
// 1 mm steps that direction is off by milliradians, so we differentiate a least-squares cubic in
// chord length over the first seven points. Measured against a quadratic over five: Table 2's
// curve 2.6 um RMS instead of 2.9, an exact cubic 0.06 um instead of 1.2, a 2 um-noise arc 3.8 um
// instead of 3.1 (the cubic passes more noise into the direction).
Point3 end_tangent(const std::vector<Point3>& points, bool from_end) {
  constexpr int kOrder = 3;
  const size_t m = std::min<size_t>(points.size(), 7);
  const int order = static_cast<int>(std::min<size_t>(kOrder, m - 1));
  auto point = [&](size_t k) { return from_end ? points[points.size() - 1 - k] : points[k]; };
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(order + 1, order + 1);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(order + 1, 3);
  double s = 0, scale = 0;
  for (size_t k = 1; k < m; ++k) scale += norm(point(k) - point(k - 1));
  for (size_t k = 0; k < m; ++k) {
    if (k > 0) s += norm(point(k) - point(k - 1)) / scale;
    Eigen::VectorXd basis(order + 1);
    for (int e = 0; e <= order; ++e) basis(e) = std::pow(s, e);
    normal += basis * basis.transpose();
    const Point3 q = point(k) - point(0);
    rhs += basis * Eigen::RowVector3d(q.x, q.y, q.z);
  }
  const Eigen::MatrixXd coefficients = normal.ldlt().solve(rhs);
  Point3 tangent{coefficients(1, 0), coefficients(1, 1), coefficients(1, 2)};
  const double length = norm(tangent);
  if (!(length > 0) || !std::isfinite(length)) return point(1) - point(0);
  return (1.0 / length) * tangent;
}

// The best (a, b) for `error` by progressive search. Hamdan 2010 steps t and s through [0, 1] in steps
// of 0.1 (its delta t); we do the same on an 11 x 11 grid over [lo, hi] in each parameter, then
// narrow: a 7 x 7 grid of a third of the previous step around the best pair, re-centred until the
// best stays put (the error has long valleys where the two points trade against each other), until
// the step is below `resolution`. Parameters outside [lo, hi] are not tried when `bounded`.
struct SearchResult {
  double a = 0, b = 0, error = HUGE_VAL;
};

SearchResult progressive_search(double lo_a, double hi_a, double lo_b, double hi_b, bool bounded, double resolution,
                                const std::function<double(double, double)>& error) {
  SearchResult best;
  auto consider = [&](double a, double b) {
    if (bounded) {
      a = std::clamp(a, lo_a, hi_a);
      b = std::clamp(b, lo_b, hi_b);
    }
    const double e = error(a, b);
    if (e < best.error) best = {a, b, e};
  };
  constexpr int kFirstSteps = 10;
  double step_a = (hi_a - lo_a) / kFirstSteps, step_b = (hi_b - lo_b) / kFirstSteps;
  for (int i = 0; i <= kFirstSteps; ++i) {
    for (int j = 0; j <= kFirstSteps; ++j) consider(lo_a + step_a * i, lo_b + step_b * j);
  }
  while (std::max(step_a, step_b) > resolution) {
    step_a /= 3;
    step_b /= 3;
    for (int moves = 0; moves < 100; ++moves) {
      const SearchResult centre = best;
      for (int i = -3; i <= 3; ++i) {
        for (int j = -3; j <= 3; ++j) {
          if (i != 0 || j != 0) consider(centre.a + i * step_a, centre.b + j * step_b);
        }
      }
      if (best.a == centre.a && best.b == centre.b) break;
    }
  }
  return best;
}

struct TangentSearch {
  Point3 p2, p3, meet;
  bool tangents_meet = false;
  double error = 0;
};

// Hamdan 2010 steps 1-13: P2 = P1 + a d1 and P3 = P4 + b d4 on the end tangents, a from P1 to P^c and
// b from P4 to P^c, by progressive search. Negative steps would reverse an end tangent and are not
// tried; neither are polygons that fold back along the chord, whose curves loop and can pass near
// every point while following none (the orthogonal error alone cannot see that).
TangentSearch search_along_tangents(const std::vector<Point3>& ordered, double resolution_fraction,
                                    const std::function<double(const Point3&, const Point3&)>& error) {
  const Point3 p1 = ordered.front(), p4 = ordered.back();
  const double chord = norm(p4 - p1);
  if (!(chord > 0)) throw FitError("a boundary or diagonal curve starts and ends at the same point");
  const Point3 d1 = end_tangent(ordered, false), d4 = end_tangent(ordered, true);
  TangentSearch out;
  double range_a = chord, range_b = chord;
  Point3 meet;
  if (tangent_intersection(p1, p1 + d1, p4, p4 + d4, meet)) {
    const double a = dot(meet - p1, d1), b = dot(meet - p4, d4);
    // Tangents that meet behind an end point (an S-shaped curve) or far beyond the chord give no
    // useful segment; the chord length then bounds the search, as it bounds any convex control polygon.
    if (a > 1e-6 * chord && b > 1e-6 * chord && a < 10 * chord && b < 10 * chord) {
      range_a = a;
      range_b = b;
      out.tangents_meet = true;
    }
  }
  out.meet = out.tangents_meet ? meet : p1 + range_a * d1;
  const Point3 along = (1.0 / chord) * (p4 - p1);
  const SearchResult best = progressive_search(0, range_a, 0, range_b, true, resolution_fraction * chord, [&](double a, double b) {
    const Point3 p2 = p1 + a * d1, p3 = p4 + b * d4;
    if (dot(p3 - p2, along) < 0) return HUGE_VAL;
    return error(p2, p3);
  });
  out.p2 = p1 + best.a * d1;
  out.p3 = p4 + best.b * d4;
  out.error = best.error;
  return out;
}

// Eq. 11 with e_i the distance from each point to its closest curve point.
double curve_rms(const CubicBezierCurve& curve, const std::vector<Point3>& points, const std::vector<double>& t0) {
  double sum = 0;
  for (size_t k = 0; k < points.size(); ++k) {
    const Point3 r = curve.at(closest_parameter(curve, points[k], t0[k])) - points[k];
    sum += dot(r, r);
  }
  return std::sqrt(sum / static_cast<double>(points.size()));
}

std::vector<double> chord_parameters(const std::vector<Point3>& points) {
  std::vector<double> t(points.size(), 0.0);
  for (size_t k = 1; k < points.size(); ++k) t[k] = t[k - 1] + norm(points[k] - points[k - 1]);
  for (double& value : t) value = t.back() > 0 ? value / t.back() : 0.0;
  return t;
}

BSplineSurface bezier_patch(const std::array<Point3, 16>& control) {
  BSplineSurface s;
  s.count_u = s.count_v = 4;
  s.knots_u = s.knots_v = {0, 0, 0, 0, 1, 1, 1, 1};
  s.control.assign(control.begin(), control.end());
  return s;
}

}  // namespace

IpsCurve ips_curve(const std::vector<Point3>& points) {
  if (points.size() < 3) {
    throw FitError("a boundary curve needs at least 3 points for its end tangents, got " + std::to_string(points.size()));
  }
  const std::vector<double> t0 = chord_parameters(points);
  IpsCurve out;
  const TangentSearch found = search_along_tangents(points, 1e-7, [&](const Point3& p2, const Point3& p3) {
    return curve_rms(CubicBezierCurve{{points.front(), p2, p3, points.back()}}, points, t0);
  });
  out.curve = CubicBezierCurve{{points.front(), found.p2, found.p3, points.back()}};
  out.meet = found.meet;
  out.tangents_meet = found.tangents_meet;
  out.rms_mm = found.error;
  return out;
}

IpsSurface fit_bezier_ips(const PointCloud& cloud, const Parameters& params) {
  if (!cloud.line) {
    throw FitError("the inverse progressive search needs scan lines: give a 'line' column or run 'digitizer segment' first");
  }
  // Lines in order, each sorted along u (this undoes serpentine reversal).
  std::map<uint32_t, std::vector<size_t>> by_line;
  for (size_t i = 0; i < cloud.points.size(); ++i) by_line[(*cloud.line)[i]].push_back(i);
  std::vector<std::vector<size_t>> lines;
  for (auto& [id, members] : by_line) {
    if (members.size() < 3) {
      throw FitError("scan line " + std::to_string(id) + " has " + std::to_string(members.size()) +
                     " points; the search needs 3 per line for the end tangents");
    }
    std::sort(members.begin(), members.end(), [&](size_t a, size_t b) { return params.uv[a].u < params.uv[b].u; });
    lines.push_back(members);
  }
  std::stable_sort(lines.begin(), lines.end(),
                   [&](const auto& a, const auto& b) { return params.uv[a[0]].v < params.uv[b[0]].v; });
  if (lines.size() < 3) throw FitError("the search needs at least 3 scan lines for the side boundaries, got " + std::to_string(lines.size()));

  auto gather = [&](const std::function<size_t(const std::vector<size_t>&)>& pick) {
    std::vector<Point3> out;
    for (const auto& line : lines) out.push_back(cloud.points[pick(line)]);
    return out;
  };
  auto line_points = [&](const std::vector<size_t>& line) {
    std::vector<Point3> out;
    for (size_t i : line) out.push_back(cloud.points[i]);
    return out;
  };
  IpsSurface result;
  result.boundary[0] = ips_curve(line_points(lines.front()));
  result.boundary[1] = ips_curve(line_points(lines.back()));
  result.boundary[2] = ips_curve(gather([](const auto& line) { return line.front(); }));
  result.boundary[3] = ips_curve(gather([](const auto& line) { return line.back(); }));

  // control[i * 4 + j]: i along the lines (u), j across them (v).
  std::array<Point3, 16> control;
  auto at = [&](int i, int j) -> Point3& { return control[static_cast<size_t>(i * 4 + j)]; };
  for (int k = 0; k < 4; ++k) {
    at(k, 0) = result.boundary[0].curve.p[k];
    at(k, 3) = result.boundary[1].curve.p[k];
    at(0, k) = result.boundary[2].curve.p[k];
    at(3, k) = result.boundary[3].curve.p[k];
  }
  // Start the interior with zero twist (P11 = P10 + P01 - P00 at each corner), which lies on the
  // diagonal tangent line the search then runs along.
  at(1, 1) = at(1, 0) + at(0, 1) - at(0, 0);
  at(2, 1) = at(2, 0) + at(3, 1) - at(3, 0);
  at(1, 2) = at(0, 2) + at(1, 3) - at(0, 3);
  at(2, 2) = at(3, 2) + at(2, 3) - at(3, 3);

  // The interior search judges whole surfaces; a spread subset of about 500 points keeps each of
  // its few hundred candidates cheap.
  const size_t stride = std::max<size_t>(1, cloud.points.size() / 500);
  std::vector<size_t> sample;
  for (size_t i = 0; i < cloud.points.size(); i += stride) sample.push_back(i);
  std::vector<UV> start(sample.size());
  for (size_t k = 0; k < sample.size(); ++k) start[k] = params.uv[sample[k]];
  auto surface_rms = [&](const BSplineSurface& s, std::vector<UV>* closest) {
    double sum = 0;
    for (size_t k = 0; k < sample.size(); ++k) {
      const Closest c = closest_point(s, cloud.points[sample[k]], start[k].u, start[k].v);
      sum += c.distance * c.distance;
      if (closest) (*closest)[k] = {c.u, c.v};
    }
    return std::sqrt(sum / static_cast<double>(sample.size()));
  };

  // Hamdan 2010: the tangents of the diagonal P11-P44 give P22 and P33, those of P14-P41 give P23 and
  // P32 (its 1-based names; ours are (1,1), (2,2) and (2,1), (1,2)). The diagonal's points are those
  // of each line nearest the diagonal in parameters. The two diagonals share the error, so they are
  // searched in turn, twice.
  auto diagonal = [&](bool rising) {
    return gather([&](const std::vector<size_t>& line) {
      const double target = rising ? params.uv[line[0]].v : 1.0 - params.uv[line[0]].v;
      size_t best = line[0];
      for (size_t i : line) {
        if (std::abs(params.uv[i].u - target) < std::abs(params.uv[best].u - target)) best = i;
      }
      return best;
    });
  };
  const std::vector<Point3> rising = diagonal(true), falling = diagonal(false);
  // Interior indices in control[]: (1,1) = 5, (2,2) = 10 on the rising diagonal, (2,1) = 9 and
  // (1,2) = 6 on the falling one.
  const size_t near_start[2] = {5, 9}, near_end[2] = {10, 6};
  for (int pass = 0; pass < 2; ++pass) {
    for (int which = 0; which < 2; ++which) {
      const TangentSearch found = search_along_tangents(which == 0 ? rising : falling, 1e-4, [&](const Point3& p2, const Point3& p3) {
        std::array<Point3, 16> trial = control;
        trial[near_start[which]] = p2;
        trial[near_end[which]] = p3;
        return surface_rms(bezier_patch(trial), nullptr);
      });
      // Keep the searched pair only if it beats the current interior (the zero-twist start is not
      // always on the search grid).
      if (found.error < surface_rms(bezier_patch(control), nullptr)) {
        control[near_start[which]] = found.p2;
        control[near_end[which]] = found.p3;
      }
      surface_rms(bezier_patch(control), &start);
    }
  }
  // Beyond the paper: the diagonal tangent lines start flat where the corners are flat, so a bump
  // inside a flat border (a boss on a plate) cannot be reached along them. The same progressive
  // search then moves each diagonal's pair along the patch normal at its corner; it keeps a move
  // only where it lowers the error, so on Hamdan's (2010) kind of parts it changes little.
  auto corner_normal = [&](size_t index) {
    const int i = static_cast<int>(index / 4) == 1 ? 0 : 3, j = index % 4 == 1 ? 0 : 3;
    const int di = i == 0 ? 1 : -1, dj = j == 0 ? 1 : -1;
    const Point3 n = cross(at(i + di, j) - at(i, j), at(i, j + dj) - at(i, j));
    const double length = norm(n);
    return length > 0 ? (1.0 / length) * n : Point3{0, 0, 1};
  };
  double reach = 0;
  for (const Point3& q : cloud.points) reach = std::max(reach, norm(q - at(0, 0)));
  for (int pass = 0; pass < 2; ++pass) {
    for (int which = 0; which < 2; ++which) {
      const size_t first = near_start[which], second = near_end[which];
      const Point3 n1 = corner_normal(first), n2 = corner_normal(second);
      const Point3 base1 = control[first], base2 = control[second];
      const SearchResult best = progressive_search(-reach, reach, -reach, reach, true, 1e-4 * reach, [&](double a, double b) {
        std::array<Point3, 16> trial = control;
        trial[first] = base1 + a * n1;
        trial[second] = base2 + b * n2;
        return surface_rms(bezier_patch(trial), nullptr);
      });
      if (best.error < surface_rms(bezier_patch(control), nullptr)) {
        control[first] = base1 + best.a * n1;
        control[second] = base2 + best.b * n2;
      }
      surface_rms(bezier_patch(control), &start);
    }
  }
  result.surface = bezier_patch(control);
  result.rms_mm = surface_rms(result.surface, nullptr);
  return result;
}

}  // namespace dg::host
