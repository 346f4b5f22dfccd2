// Local plane, quadratic and cubic fits through the shared packed LDL^T solver.
#include "host/scan/local_polynomial.h"

#include <algorithm>
#include <cmath>

#include "common/fit/dense_ldlt.h"

namespace dg::host {

namespace {

using polynomial_terms::terms;

// The points' terms into the normal equations (packed lower triangle) and the right-hand side, N
// terms a point, `place(j, dx, dy, value)` giving point j's scaled offsets and value. N is fixed at
// compile time so the loops unroll: with it a variable the loop took 460 instructions a point for a
// cubic, most of the LTS filter's time. The same sums in the same order either way.
template <int N, typename Place>
void add_points(const std::vector<size_t>& indices, Place place, double* a, double* c) {
  for (size_t j : indices) {
    double dx, dy, value, t[N];
    place(j, dx, dy, value);
    terms<N>(dx, dy, t);
#pragma GCC unroll 10
    for (int r = 0; r < N; ++r) {
#pragma GCC unroll 10
      for (int k = 0; k <= r; ++k) a[fit::packed_index(r, k)] += t[r] * t[k];
      c[r] += t[r] * value;
    }
  }
}

// The shared LDL^T solver inlined whole with its size a constant: about a tenth fewer instructions
// than the generic call, which took some 3,800 to factor a cubic's 10 x 10 (the triangular loops
// stay loops at -O2). The same operations in the same order.
template <int N>
__attribute__((flatten)) bool solve_fixed(double* a, double* c, double* centre_gain) {
  double inverse_d[N];
  if (fit::ldlt_factor(a, N, inverse_d, 1e-10) != Status::kOk) return false;
  fit::ldlt_solve(a, inverse_d, N, c);
  double first_column[N] = {1};
  fit::ldlt_solve(a, inverse_d, N, first_column);
  *centre_gain = first_column[0];
  return true;
}

}  // namespace

namespace {

double dot(const double (&axis)[3], double x, double y, double z) { return axis[0] * x + axis[1] * y + axis[2] * z; }

// Its derivatives along dx and dy there.
void slope_of(const LocalPolynomial& m, double dx, double dy, double& along_x, double& along_y) {
  const double* c = m.c;
  along_x = c[1], along_y = c[2];
  if (m.order >= 2) along_x += 2 * c[3] * dx + c[4] * dy, along_y += c[4] * dx + 2 * c[5] * dy;
  if (m.order >= 3) {
    along_x += 3 * c[6] * dx * dx + 2 * c[7] * dx * dy + c[8] * dy * dy;
    along_y += c[7] * dx * dx + 2 * c[8] * dx * dy + 3 * c[9] * dy * dy;
  }
}

// At most this many Newton steps for a tilted model's height: the surface is nearly flat in its own
// frame, so the tangent plane's height is a close start and each step converges quadratically; a
// step that changes the height by less than 1e-12 mm ends it sooner. Eight, not four: on a parabola
// of curvature 2 per mm tilted 80 degrees, 0.3 mm from the centre, four steps left the height 43 nm
// off (the fifth step's size), and the seventh step was under 1e-16 mm.
constexpr int kHeightSteps = 8;

// How far a tilted model's surface lies from the point at offset `oz` above (ox, oy), along the
// normal (`miss`), and how fast that changes with oz (`rate`).
void miss_and_rate(const LocalPolynomial& m, double ox, double oy, double oz, double& miss, double& rate) {
  const double du = dot(m.axis_u, ox, oy, oz) / m.scale_x, dv = dot(m.axis_v, ox, oy, oz) / m.scale_y;
  double along_u, along_v;
  slope_of(m, du, dv, along_u, along_v);
  miss = dot(m.normal, ox, oy, oz) - polynomial_terms::value_of_order(m.order, m.c, du, dv);
  rate = m.normal[2] - along_u * m.axis_u[2] / m.scale_x - along_v * m.axis_v[2] / m.scale_y;
}

// A rate below this leaves Newton's step undefined: the vertical touches the surface there.
constexpr double kRateMin = 1e-12;

// A height whose next Newton step would move it by more than this is not one the steps reached.
constexpr double kHeightConverged_mm = 1e-9;

}  // namespace

double LocalPolynomial::tilted_at(double x, double y) const {
  const double ox = x - centre.x, oy = y - centre.y;
  // The height z where the offset along the normal equals the polynomial's, from the tangent
  // plane's height by Newton's steps.
  double oz = -(normal[0] * ox + normal[1] * oy) / normal[2];
  for (int step = 0; step < kHeightSteps; ++step) {
    double miss, rate;
    miss_and_rate(*this, ox, oy, oz, miss, rate);
    if (!(std::fabs(rate) > kRateMin)) break;
    const double change = miss / rate;
    oz -= change;
    if (!(std::fabs(change) > 1e-12)) break;
  }
  return centre.z + oz;
}

bool LocalPolynomial::height(double x, double y, double& z) const {
  z = at(x, y);
  if (!tilted) return std::isfinite(z);
  // One more step from where at() stopped tells whether it stopped on the surface: where the
  // vertical misses it, the steps wander (or stop on a zero rate) with a miss that stays large.
  double miss, rate;
  miss_and_rate(*this, x - centre.x, y - centre.y, z - centre.z, miss, rate);
  return std::isfinite(z) && std::fabs(rate) > kRateMin && std::fabs(miss / rate) <= kHeightConverged_mm;
}

namespace {

// Fits `out` (its order, centre, frame and scales set) to the points `place` gives.
template <typename Place>
bool fit_placed(const std::vector<size_t>& indices, Place place, LocalPolynomial& out) {
  const int n = out.terms();
  if (!(out.scale_x > 0) || !(out.scale_y > 0)) return false;
  if (indices.size() < static_cast<size_t>(n)) return false;
  double a[fit::packed_size(10)] = {};
  for (double& value : out.c) value = 0;
  switch (n) {
    case 3: add_points<3>(indices, place, a, out.c); break;
    case 6: add_points<6>(indices, place, a, out.c); break;
    default: add_points<10>(indices, place, a, out.c); break;
  }
  switch (n) {
    case 3: return solve_fixed<3>(a, out.c, &out.centre_gain);
    case 6: return solve_fixed<6>(a, out.c, &out.centre_gain);
    default: return solve_fixed<10>(a, out.c, &out.centre_gain);
  }
}

}  // namespace

bool fit_local_polynomial(const std::vector<Point3>& points, const std::vector<size_t>& indices, const Point3& centre,
                          int order, LocalPolynomial& out) {
  out.order = order;
  out.centre = centre;
  out.tilted = false;
  out.scale_x = out.scale_y = 0;
  for (size_t j : indices) {
    out.scale_x = std::max(out.scale_x, std::fabs(points[j].x - centre.x));
    out.scale_y = std::max(out.scale_y, std::fabs(points[j].y - centre.y));
  }
  return fit_placed(indices, [&](size_t j, double& dx, double& dy, double& value) {
    dx = (points[j].x - centre.x) / out.scale_x, dy = (points[j].y - centre.y) / out.scale_y, value = points[j].z;
  }, out);
}

bool fit_tilted_polynomial(const std::vector<Point3>& points, const std::vector<size_t>& indices, const Point3& centre,
                           const double (&normal)[3], int order, LocalPolynomial& out) {
  out.order = order;
  out.centre = centre;
  out.tilted = true;
  const double length = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
  if (!(length > 0) || !(normal[2] > 0)) return false;
  for (int k = 0; k < 3; ++k) out.normal[k] = normal[k] / length;
  // axis_u: x with its part along the normal taken out; axis_v = normal x axis_u.
  const double* n = out.normal;
  double u[3] = {1 - n[0] * n[0], -n[0] * n[1], -n[0] * n[2]};
  const double u_length = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (int k = 0; k < 3; ++k) out.axis_u[k] = u[k] / u_length;
  out.axis_v[0] = n[1] * out.axis_u[2] - n[2] * out.axis_u[1];
  out.axis_v[1] = n[2] * out.axis_u[0] - n[0] * out.axis_u[2];
  out.axis_v[2] = n[0] * out.axis_u[1] - n[1] * out.axis_u[0];
  out.scale_x = out.scale_y = 0;
  for (size_t j : indices) {
    const double ox = points[j].x - centre.x, oy = points[j].y - centre.y, oz = points[j].z - centre.z;
    out.scale_x = std::max(out.scale_x, std::fabs(dot(out.axis_u, ox, oy, oz)));
    out.scale_y = std::max(out.scale_y, std::fabs(dot(out.axis_v, ox, oy, oz)));
  }
  return fit_placed(indices, [&](size_t j, double& dx, double& dy, double& value) {
    const double ox = points[j].x - centre.x, oy = points[j].y - centre.y, oz = points[j].z - centre.z;
    dx = dot(out.axis_u, ox, oy, oz) / out.scale_x, dy = dot(out.axis_v, ox, oy, oz) / out.scale_y;
    value = dot(out.normal, ox, oy, oz);
  }, out);
}

}  // namespace dg::host
