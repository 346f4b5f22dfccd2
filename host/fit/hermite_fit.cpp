// Li and Zhang's (2013) construction with its free parameters chosen by a rule instead of by trial:
//  - parameters are chord lengths averaged over the grid's rows and columns (the paper steps by 1
//    per point, which on its sphere grid x, y in {-2, -1, 1, 2} stretches the middle cell);
//  - tangents: the three-tangent-vector (C2 spline) equations, eq. 5, in their form for unequal
//    parameter steps; the end tangents, which the paper leaves to p0u(1), p3u(1) by trial, are the
//    ones that make n . t = 0 (eq. 6) hold and are otherwise nearest to the derivative of the cubic
//    through the four end points, projected onto the end's tangent plane. That cubic's derivative
//    is exact for a cubic and O(h^3) for any smooth curve, where a minimum-bending (natural) end
//    would flatten a sphere's rim;
//  - twists: the paper's steps 3-4 (spline derivatives of the u-tangents down the two boundary
//    columns, then of the v-tangents along every row), with the corner twists estimated the same
//    way as the end tangents. The result is the C2 bicubic spline interpolant with those ends.
#include "host/fit/hermite_fit.h"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <string>

#include "host/scan/segment.h"
#include "host/fit/fit_error.h"
#include "host/geometry/vec3.h"

namespace dg::host {

namespace {

Point3 project_to_plane(Point3 d, Point3 n) { return d - dot(d, n) * n; }

// Derivative at t[at] (the first or last index) of the polynomial through up to four points there.
Point3 end_derivative(const std::vector<Point3>& f, const std::vector<double>& t, bool first) {
  const size_t count = f.size() < 4 ? f.size() : 4;
  std::vector<size_t> idx;
  for (size_t k = 0; k < count; ++k) idx.push_back(first ? k : f.size() - 1 - k);
  const double x = t[idx[0]];
  // d/dx of the Lagrange basis l_a at x = t[idx[0]].
  Point3 d;
  for (size_t a = 0; a < count; ++a) {
    double derivative = 0;
    if (a == 0) {
      for (size_t b = 1; b < count; ++b) derivative += 1.0 / (x - t[idx[b]]);
    } else {
      double num = 1, den = 1;
      for (size_t b = 0; b < count; ++b) {
        if (b == a) continue;
        den *= t[idx[a]] - t[idx[b]];
        if (b != 0) num *= x - t[idx[b]];
      }
      derivative = num / den;
    }
    d += derivative * f[idx[a]];
  }
  return d;
}

// Solves the interior equations of the C2 spline for right-hand sides `rhs` (rows 1..n-2), with
// the end derivatives fixed at zero; Thomas' algorithm, one scalar matrix for all components.
std::vector<Point3> solve_interior(const std::vector<double>& h, std::vector<Point3> rhs) {
  const size_t n = rhs.size();
  std::vector<Point3> x(n);
  if (n < 3) return x;
  std::vector<double> c(n, 0.0);
  // Row k (1..n-2): h[k] x[k-1] + 2 (h[k-1] + h[k]) x[k] + h[k-1] x[k+1].
  double beta = 2 * (h[0] + h[1]);
  c[1] = h[0] / beta;
  rhs[1] = (1.0 / beta) * rhs[1];
  for (size_t k = 2; k + 1 < n; ++k) {
    const double a = h[k];
    beta = 2 * (h[k - 1] + h[k]) - a * c[k - 1];
    c[k] = h[k - 1] / beta;
    rhs[k] = (1.0 / beta) * (rhs[k] - a * rhs[k - 1]);
  }
  x[n - 2] = rhs[n - 2];
  for (size_t k = n - 2; k-- > 1;) x[k] = rhs[k] - c[k] * x[k + 1];
  return x;
}

std::vector<double> steps(const std::vector<double>& t) {
  std::vector<double> h;
  for (size_t k = 0; k + 1 < t.size(); ++k) h.push_back(t[k + 1] - t[k]);
  return h;
}

std::vector<Point3> spline_rhs(const std::vector<Point3>& f, const std::vector<double>& h) {
  std::vector<Point3> rhs(f.size());
  for (size_t k = 1; k + 1 < f.size(); ++k) {
    rhs[k] = 3.0 * ((h[k] / h[k - 1]) * (f[k] - f[k - 1]) + (h[k - 1] / h[k]) * (f[k + 1] - f[k]));
  }
  return rhs;
}

// How the interior derivatives depend on the two end derivatives: d_k = a_k + b_k d_0 + c_k d_n.
struct EndDependence {
  std::vector<Point3> a;
  std::vector<double> b, c;
};

EndDependence end_dependence(const std::vector<Point3>& f, const std::vector<double>& h) {
  const size_t n = f.size();
  EndDependence e;
  e.a = solve_interior(h, spline_rhs(f, h));
  // Unit end derivatives along x give the scalar weights (the matrix is the same per component).
  std::vector<Point3> r0(n), r1(n);
  if (n >= 3) {
    r0[1] = -h[1] * Point3{1, 0, 0};
    r1[n - 2] += -h[n - 3] * Point3{1, 0, 0};
  }
  const std::vector<Point3> x0 = solve_interior(h, r0), x1 = solve_interior(h, r1);
  e.b.assign(n, 0.0);
  e.c.assign(n, 0.0);
  for (size_t k = 1; k + 1 < n; ++k) {
    e.b[k] = x0[k].x;
    e.c[k] = x1[k].x;
  }
  e.a[0] = e.a[n - 1] = Point3{};
  e.b[0] = 1;
  e.c[n - 1] = 1;
  return e;
}

Point3 unit(Point3 n) { return (1.0 / norm(n)) * n; }

}  // namespace

std::vector<Point3> periodic_derivatives(const std::vector<Point3>& f, const std::vector<double>& t) {
  // m distinct points around the loop; the C2 equation at every one of them, indices modulo m.
  const int m = static_cast<int>(f.size()) - 1;
  const std::vector<double> h = steps(t);  // h[k]: from point k to k + 1, the last closing the loop
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd rhs(m, 3);
  for (int k = 0; k < m; ++k) {
    const int prev = (k + m - 1) % m, next = (k + 1) % m;
    const double hp = h[static_cast<size_t>(prev)], hk = h[static_cast<size_t>(k)];
    entries.emplace_back(k, prev, hk);
    entries.emplace_back(k, k, 2 * (hp + hk));
    entries.emplace_back(k, next, hp);
    const Point3 r = 3.0 * ((hk / hp) * (f[static_cast<size_t>(k)] - f[static_cast<size_t>(prev)]) +
                            (hp / hk) * (f[static_cast<size_t>(k + 1)] - f[static_cast<size_t>(k)]));
    rhs.row(k) << r.x, r.y, r.z;
  }
  Eigen::SparseMatrix<double> a(m, m);
  a.setFromTriplets(entries.begin(), entries.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(a);
  if (lu.info() != Eigen::Success) throw FitError("the closed spline's equations are singular");
  const Eigen::MatrixXd x = lu.solve(rhs);
  std::vector<Point3> d;
  for (int k = 0; k < m; ++k) d.push_back({x(k, 0), x(k, 1), x(k, 2)});
  d.push_back(d.front());
  return d;
}

std::vector<Point3> spline_derivatives(const std::vector<Point3>& f, const std::vector<double>& t, Point3 first,
                                       Point3 last) {
  const EndDependence e = end_dependence(f, steps(t));
  std::vector<Point3> d(f.size());
  for (size_t k = 0; k < f.size(); ++k) d[k] = e.a[k] + e.b[k] * first + e.c[k] * last;
  return d;
}

std::vector<Point3> constrained_tangents(const std::vector<Point3>& p, const std::vector<Point3>& normals,
                                         const std::vector<double>& t) {
  const size_t n = p.size();
  const EndDependence e = end_dependence(p, steps(t));
  std::vector<Point3> nn;
  for (const Point3& v : normals) nn.push_back(unit(v));
  const Point3 target0 = project_to_plane(end_derivative(p, t, true), nn[0]);
  const Point3 target1 = project_to_plane(end_derivative(p, t, false), nn[n - 1]);
  // Least squares in x = (d_0, d_n): W (n_k . d_k)^2 for every k, plus |d_end - target|^2. The
  // weight makes the normal constraints exact wherever six unknowns can meet them all.
  constexpr double kConstraintWeight = 1e8;
  constexpr double kMinEndInfluence = 0.1;
  Eigen::Matrix<double, 6, 6> ata = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> atb = Eigen::Matrix<double, 6, 1>::Zero();
  auto add_row = [&](const Eigen::Matrix<double, 1, 6>& row, double value, double weight) {
    ata += weight * row.transpose() * row;
    atb += weight * row.transpose() * value;
  };
  for (size_t k = 0; k < n; ++k) {
    // A constraint the end tangents barely move (an interior point: their influence decays by
    // about 0.27 a step) cannot be met by them when the points are noisy; weighted as an exact
    // one, it would swing them by the noise over that influence (2 um of noise in z put a sphere's
    // surface 54 um off between the points: HermiteFit.NoisyPointsDoNotSwingTheEndTangents). Such
    // constraints are left to the data.
    if (std::max(std::fabs(e.b[k]), std::fabs(e.c[k])) < kMinEndInfluence) continue;
    Eigen::Matrix<double, 1, 6> row;
    const Point3 m = nn[k];
    row << e.b[k] * m.x, e.b[k] * m.y, e.b[k] * m.z, e.c[k] * m.x, e.c[k] * m.y, e.c[k] * m.z;
    add_row(row, -dot(m, e.a[k]), kConstraintWeight);
  }
  const Point3 targets[2] = {target0, target1};
  for (int end = 0; end < 2; ++end) {
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::Matrix<double, 1, 6> row = Eigen::Matrix<double, 1, 6>::Zero();
      row(end * 3 + axis) = 1;
      const Point3 g = targets[end];
      add_row(row, axis == 0 ? g.x : axis == 1 ? g.y : g.z, 1.0);
    }
  }
  const Eigen::Matrix<double, 6, 1> x = ata.ldlt().solve(atb);
  const Point3 d0{x(0), x(1), x(2)}, d1{x(3), x(4), x(5)};
  std::vector<Point3> d(n);
  for (size_t k = 0; k < n; ++k) d[k] = e.a[k] + e.b[k] * d0 + e.c[k] * d1;
  return d;
}

HermiteGrid hermite_grid(const PointCloud& cloud, const std::string& name) {
  if (!cloud.normal) throw FitError(name + ": a Hermite surface needs normals: give nx,ny,nz columns");
  const std::vector<uint32_t> lines = cloud.line ? *cloud.line : segment_lines(cloud.points);
  HermiteGrid g;
  size_t start = 0;
  Point3 first_direction;
  while (start < cloud.points.size()) {
    size_t end = start;
    while (end < cloud.points.size() && lines[end] == lines[start]) ++end;
    const int length = static_cast<int>(end - start);
    if (g.rows > 0 && length != g.cols) {
      throw FitError(name + ": line " + std::to_string(g.rows) + " has " + std::to_string(length) + " points, line 0 has " +
                     std::to_string(g.cols) + "; a Hermite surface needs a grid (every line the same length)");
    }
    const Point3 direction = cloud.points[end - 1] - cloud.points[start];
    if (g.rows == 0) {
      g.cols = length;
      first_direction = direction;
    }
    const bool reversed = dot(direction, first_direction) < 0;
    for (int k = 0; k < length; ++k) {
      const size_t at = reversed ? end - 1 - static_cast<size_t>(k) : start + static_cast<size_t>(k);
      g.points.push_back(cloud.points[at]);
      g.normals.push_back((*cloud.normal)[at]);
    }
    ++g.rows;
    start = end;
  }
  return g;
}

HermiteResult fit_hermite(const HermiteGrid& g) {
  if (g.rows < 3 || g.cols < 3) {
    throw FitError("a Hermite surface needs a grid of at least 3 x 3 points with normals; got " +
                   std::to_string(g.cols) + " x " + std::to_string(g.rows));
  }
  const size_t count = static_cast<size_t>(g.rows) * static_cast<size_t>(g.cols);
  if (g.points.size() != count || g.normals.size() != count) throw FitError("the grid's points and normals do not fill it");
  auto where = [&](size_t k) {
    return "row " + std::to_string(k / static_cast<size_t>(g.cols)) + ", point " + std::to_string(k % static_cast<size_t>(g.cols));
  };
  for (size_t k = 0; k < count; ++k) {
    const Point3 p = g.points[k], n = g.normals[k];
    if (!std::isfinite(p.x + p.y + p.z) || !std::isfinite(n.x + n.y + n.z)) throw FitError("a non-finite value at " + where(k));
    if (!(norm(n) > 1e-12)) throw FitError("the normal at " + where(k) + " has zero length");
  }
  auto at = [&](const std::vector<Point3>& v, int row, int col) { return v[static_cast<size_t>(row) * g.cols + col]; };
  // Chord-length parameters shared by all rows (u) and all columns (v), so the patches meet.
  HermiteResult r;
  r.u.assign(static_cast<size_t>(g.cols), 0.0);
  r.v.assign(static_cast<size_t>(g.rows), 0.0);
  for (int c = 1; c < g.cols; ++c) {
    double sum = 0;
    for (int row = 0; row < g.rows; ++row) sum += norm(at(g.points, row, c) - at(g.points, row, c - 1));
    if (!(sum > 0)) throw FitError("columns " + std::to_string(c - 1) + " and " + std::to_string(c) + " of the grid are the same points");
    r.u[c] = r.u[c - 1] + sum / g.rows;
  }
  for (int row = 1; row < g.rows; ++row) {
    double sum = 0;
    for (int c = 0; c < g.cols; ++c) sum += norm(at(g.points, row, c) - at(g.points, row - 1, c));
    if (!(sum > 0)) throw FitError("rows " + std::to_string(row - 1) + " and " + std::to_string(row) + " of the grid are the same points");
    r.v[row] = r.v[row - 1] + sum / g.cols;
  }
  // Steps 1-2: tangents along every row (u) and every column (v). A line is `length` grid points
  // from `first`, `stride` apart.
  std::vector<Point3> tu(count), tv(count);
  auto line_tangents = [&](size_t first, size_t stride, int length, const std::vector<double>& t, std::vector<Point3>& out) {
    std::vector<Point3> p, n;
    for (int k = 0; k < length; ++k) {
      p.push_back(g.points[first + static_cast<size_t>(k) * stride]);
      n.push_back(g.normals[first + static_cast<size_t>(k) * stride]);
    }
    // A closed line has no ends to choose: its tangents are the periodic spline's.
    const bool closed = stride == 1 ? r.closed_u : r.closed_v;
    const std::vector<Point3> d = closed ? periodic_derivatives(p, t) : constrained_tangents(p, n, t);
    for (int k = 0; k < length; ++k) out[first + static_cast<size_t>(k) * stride] = d[static_cast<size_t>(k)];
  };
  const size_t cols = static_cast<size_t>(g.cols);
  // Closed: every line in that direction ends on its first point (Li and Zhang's (2013) cylinder and cone).
  double extent = 0;
  for (const Point3& p : g.points) extent = std::max(extent, norm(p - g.points.front()));
  r.closed_u = r.closed_v = true;
  for (int row = 0; row < g.rows; ++row) r.closed_u = r.closed_u && norm(at(g.points, row, 0) - at(g.points, row, g.cols - 1)) <= 1e-9 * extent;
  for (int c = 0; c < g.cols; ++c) r.closed_v = r.closed_v && norm(at(g.points, 0, c) - at(g.points, g.rows - 1, c)) <= 1e-9 * extent;
  for (int row = 0; row < g.rows; ++row) line_tangents(static_cast<size_t>(row) * cols, 1, g.cols, r.u, tu);
  for (int c = 0; c < g.cols; ++c) line_tangents(static_cast<size_t>(c), cols, g.rows, r.v, tv);
  for (size_t k = 0; k < count; ++k) {
    const Point3 n = unit(g.normals[k]);
    for (const Point3& t : {tu[k], tv[k]}) {
      const double residual = std::fabs(dot(n, t)) / (norm(t) > 0 ? norm(t) : 1.0);
      if (residual > r.normal_residual_max) r.normal_residual_max = residual;
    }
  }
  // Steps 3-4: twists. Corner twists from the end rule applied to the u-tangents down the boundary
  // columns and the v-tangents along the boundary rows (their mean: the two estimate one thing).
  auto column_of = [&](const std::vector<Point3>& v, int c) {
    std::vector<Point3> out;
    for (int row = 0; row < g.rows; ++row) out.push_back(at(v, row, c));
    return out;
  };
  auto row_of = [&](const std::vector<Point3>& v, int row) {
    return std::vector<Point3>(v.begin() + static_cast<long>(row) * g.cols, v.begin() + static_cast<long>(row + 1) * g.cols);
  };
  auto corner_twist = [&](int row, int c) {
    const Point3 a = end_derivative(column_of(tu, c), r.v, row == 0);
    const Point3 b = end_derivative(row_of(tv, row), r.u, c == 0);
    return 0.5 * (a + b);
  };
  std::vector<Point3> twist(count);
  if (r.closed_v || r.closed_u) {
    // Around a closed direction the twists are the periodic derivatives of the other direction's
    // tangents: no corners, nothing to estimate.
    if (r.closed_v) {
      for (int c = 0; c < g.cols; ++c) {
        const std::vector<Point3> w = periodic_derivatives(column_of(tu, c), r.v);
        for (int row = 0; row < g.rows; ++row) twist[static_cast<size_t>(row) * g.cols + c] = w[static_cast<size_t>(row)];
      }
    } else {
      for (int row = 0; row < g.rows; ++row) {
        const std::vector<Point3> w = periodic_derivatives(row_of(tv, row), r.u);
        for (int c = 0; c < g.cols; ++c) twist[static_cast<size_t>(row) * g.cols + c] = w[static_cast<size_t>(c)];
      }
    }
  } else {
    for (int c : {0, g.cols - 1}) {
      const std::vector<Point3> w = spline_derivatives(column_of(tu, c), r.v, corner_twist(0, c), corner_twist(g.rows - 1, c));
      for (int row = 0; row < g.rows; ++row) twist[static_cast<size_t>(row) * g.cols + c] = w[static_cast<size_t>(row)];
    }
    for (int row = 0; row < g.rows; ++row) {
      const std::vector<Point3> w = spline_derivatives(row_of(tv, row), r.u, at(twist, row, 0), at(twist, row, g.cols - 1));
      for (int c = 0; c < g.cols; ++c) twist[static_cast<size_t>(row) * g.cols + c] = w[static_cast<size_t>(c)];
    }
  }
  // Step 5: each cell's Hermite patch as its Bezier net (b1 = p0 + h t0 / 3, b11 adds h_u h_v w / 9).
  BSplineSurface& s = r.surface;
  s.degree_u = s.degree_v = 3;
  s.count_u = 3 * (g.cols - 1) + 1;
  s.count_v = 3 * (g.rows - 1) + 1;
  auto knots = [](const std::vector<double>& t) {
    std::vector<double> k(4, t.front());
    for (size_t i = 1; i + 1 < t.size(); ++i) k.insert(k.end(), 3, t[i]);
    k.insert(k.end(), 4, t.back());
    return k;
  };
  s.knots_u = knots(r.u);
  s.knots_v = knots(r.v);
  s.control.assign(static_cast<size_t>(s.count_u) * s.count_v, Point3{});
  for (int row = 0; row < g.rows; ++row) {
    for (int c = 0; c < g.cols; ++c) {
      const size_t k = static_cast<size_t>(row) * g.cols + c;
      // The control points around grid point (c, row), in the cells on either side.
      for (int su = -1; su <= 1; ++su) {
        for (int sv = -1; sv <= 1; ++sv) {
          const int iu = 3 * c + su, iv = 3 * row + sv;
          if (iu < 0 || iv < 0 || iu >= s.count_u || iv >= s.count_v) continue;
          const double hu = su < 0 ? r.u[c] - r.u[c - 1] : su > 0 ? r.u[c + 1] - r.u[c] : 0;
          const double hv = sv < 0 ? r.v[row] - r.v[row - 1] : sv > 0 ? r.v[row + 1] - r.v[row] : 0;
          s.at(iu, iv) = g.points[k] + (su * hu / 3) * tu[k] + (sv * hv / 3) * tv[k] + (su * sv * hu * hv / 9) * twist[k];
        }
      }
    }
  }
  return r;
}

}  // namespace dg::host
