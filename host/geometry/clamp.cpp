// Boehm knot insertion along one direction of the net, then the parts outside the domain dropped.
#include "host/geometry/clamp.h"

#include <vector>

#include "host/geometry/vec3.h"

namespace dg::host {
namespace {

// The knots of one direction and the rows of control points along it.
struct Direction {
  std::vector<double> knots;
  int degree = 3;
  std::vector<std::vector<Point3>> rows;  // rows[r][i]
};

// Inserts t once (Boehm) into every row.
void insert_knot(Direction& d, double t) {
  const int p = d.degree;
  const int n = static_cast<int>(d.rows.front().size());
  int k = p;  // the span with knots[k] <= t < knots[k + 1]
  while (k + 1 < n && d.knots[static_cast<size_t>(k + 1)] <= t) ++k;
  for (auto& row : d.rows) {
    std::vector<Point3> next(static_cast<size_t>(n + 1));
    for (int i = 0; i <= n; ++i) {
      if (i <= k - p) {
        next[static_cast<size_t>(i)] = row[static_cast<size_t>(i)];
      } else if (i > k) {
        next[static_cast<size_t>(i)] = row[static_cast<size_t>(i - 1)];
      } else {
        const double lo = d.knots[static_cast<size_t>(i)], hi = d.knots[static_cast<size_t>(i + p)];
        const double a = hi > lo ? (t - lo) / (hi - lo) : 0.0;
        next[static_cast<size_t>(i)] = (1 - a) * row[static_cast<size_t>(i - 1)] + a * row[static_cast<size_t>(i)];
      }
    }
    row.swap(next);
  }
  d.knots.insert(d.knots.begin() + k + 1, t);
}

void clamp(Direction& d) {
  const int p = d.degree;
  const double lo = d.knots[static_cast<size_t>(p)];
  const double hi = d.knots[d.knots.size() - 1 - static_cast<size_t>(p)];
  auto multiplicity = [&](double t) {
    int m = 0;
    for (double k : d.knots) m += k == t;
    return m;
  };
  while (multiplicity(lo) < p) insert_knot(d, lo);
  while (multiplicity(hi) < p) insert_knot(d, hi);
  // With lo of multiplicity p, the curve at lo is control point `first`; drop those before it and
  // the knots outside [lo, hi], then repeat the end knots to degree + 1.
  size_t first_lo = 0;
  while (d.knots[first_lo] < lo) ++first_lo;
  size_t last_hi = d.knots.size() - 1;
  while (d.knots[last_hi] > hi) --last_hi;
  const size_t first = first_lo - 1;  // the control point the curve passes through at lo
  std::vector<double> knots;
  knots.push_back(lo);
  for (size_t i = first_lo; i <= last_hi; ++i) knots.push_back(d.knots[i]);
  knots.push_back(hi);
  const size_t count = knots.size() - static_cast<size_t>(p) - 1;
  for (auto& row : d.rows) row = std::vector<Point3>(row.begin() + static_cast<long>(first), row.begin() + static_cast<long>(first + count));
  d.knots = knots;
}

bool is_clamped(const std::vector<double>& knots, int degree) {
  for (int i = 1; i <= degree; ++i) {
    if (knots[static_cast<size_t>(i)] != knots[0] || knots[knots.size() - 1 - static_cast<size_t>(i)] != knots.back()) return false;
  }
  return true;
}

// The same surface with u and v exchanged, so one routine serves both directions.
BSplineSurface transposed(const BSplineSurface& s) {
  BSplineSurface t;
  t.degree_u = s.degree_v;
  t.degree_v = s.degree_u;
  t.count_u = s.count_v;
  t.count_v = s.count_u;
  t.knots_u = s.knots_v;
  t.knots_v = s.knots_u;
  t.control.resize(s.control.size());
  for (int i = 0; i < s.count_u; ++i)
    for (int j = 0; j < s.count_v; ++j) t.at(j, i) = s.at(i, j);
  return t;
}

BSplineSurface clamp_along_u(const BSplineSurface& s) {
  if (is_clamped(s.knots_u, s.degree_u)) return s;
  Direction d{s.knots_u, s.degree_u, {}};
  for (int j = 0; j < s.count_v; ++j) {
    d.rows.emplace_back();
    for (int i = 0; i < s.count_u; ++i) d.rows.back().push_back(s.at(i, j));
  }
  clamp(d);
  BSplineSurface out = s;
  out.knots_u = d.knots;
  out.count_u = static_cast<int>(d.rows.front().size());
  out.control.assign(static_cast<size_t>(out.count_u) * out.count_v, Point3{});
  for (int j = 0; j < out.count_v; ++j)
    for (int i = 0; i < out.count_u; ++i) out.at(i, j) = d.rows[static_cast<size_t>(j)][static_cast<size_t>(i)];
  return out;
}

}  // namespace

BSplineSurface clamp_ends(const BSplineSurface& s) {
  return transposed(clamp_along_u(transposed(clamp_along_u(s))));
}

}  // namespace dg::host
