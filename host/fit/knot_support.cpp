// Greedy matching of sites to basis functions: taking the smallest usable site for each function in
// turn finds a matching whenever one exists, because supports move monotonically with the index.
#include "host/fit/knot_support.h"

#include "common/fit/bspline_basis.h"
#include "host/fit/bucket_sort.h"
#include "host/geometry/bspline_surface.h"
#include "host/fit/site_index.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dg::host {


std::vector<double> distinct_sites(const std::vector<UV>& uv, bool along_u, double merge) {
  std::vector<double> values;
  values.reserve(uv.size());
  for (const UV& p : uv) values.push_back(along_u ? p.u : p.v);
  sort_by_buckets(values, merge, [](double v) { return v; });
  return sites_of_sorted(values, merge);
}

std::vector<double> sites_of_sorted(const std::vector<double>& values, double merge) {
  SiteGrouping grouping(merge);
  for (double v : values) grouping.add(v);
  return grouping.finish();
}

double site_merge_distance(size_t points) {
  return 0.1 / std::max(1.0, std::sqrt(static_cast<double>(points)));
}

std::vector<RampPoint> ramp_points(const std::vector<double>& knots, int degree, const std::vector<double>& sites) {
  std::vector<RampPoint> ramps;
  if (degree < 2) return ramps;
  const int count = static_cast<int>(knots.size()) - degree - 1;
  // Interior knots with multiplicity exactly `degree`: first index of each run.
  for (int a = degree + 1; a + 2 * degree <= count; ++a) {
    const double ta = knots[static_cast<size_t>(a)];
    if (knots[static_cast<size_t>(a - 1)] == ta) continue;
    if (knots[static_cast<size_t>(a + degree - 1)] != ta || knots[static_cast<size_t>(a + degree)] == ta) continue;
    const int b = a + degree;  // the next knot run must start right after, also of multiplicity degree
    const double tb = knots[static_cast<size_t>(b)];
    if (!(tb > ta) || tb >= 1.0 || b + degree > count) continue;
    if (knots[static_cast<size_t>(b + degree - 1)] != tb || knots[static_cast<size_t>(b + degree)] == tb) continue;
    const bool empty = std::none_of(sites.begin(), sites.end(), [&](double t) { return t > ta && t < tb; });
    if (!empty) continue;
    // N_{a-1} is 1 at ta and N_{b-1} is 1 at tb; the degree - 1 between them live inside (ta, tb).
    const int left = a - 1, right = b - 1;
    const double gl = greville(knots, degree, left), gr = greville(knots, degree, right);
    for (int i = left + 1; i < right; ++i) {
      ramps.push_back({i, left, right, (greville(knots, degree, i) - gl) / (gr - gl)});
    }
  }
  return ramps;
}

int schoenberg_whitney_gap(const std::vector<double>& knots, int degree, const std::vector<double>& sites,
                           double min_basis) {
  const int count = static_cast<int>(knots.size()) - degree - 1;
  const std::vector<RampPoint> ramps = ramp_points(knots, degree, sites);
  size_t next = 0;
  for (int i = 0; i < count; ++i) {
    if (std::any_of(ramps.begin(), ramps.end(), [&](const RampPoint& r) { return r.index == i; })) continue;
    const double lo = knots[static_cast<size_t>(i)], hi = knots[static_cast<size_t>(i + degree + 1)];
    // N_i is non-zero on (lo, hi); a clamped first function is 1 at lo, the last at hi.
    while (next < sites.size()) {
      const double t = sites[next];
      bool inside = (t > lo && t < hi) || (i == 0 && t == lo) || (i == count - 1 && t == hi);
      if (inside && min_basis > 0) {
        const int span = fit::find_span(count, degree, t, knots.data());
        double n[fit::kMaxDegree + 1];
        fit::bspline_basis(span, degree, t, knots.data(), n);
        const int k = i - (span - degree);
        inside = k >= 0 && k <= degree && n[k] >= min_basis;
      }
      if (inside) break;
      if (t >= hi) return i;  // sites are sorted: none later lies in this support either
      ++next;
    }
    if (next == sites.size()) return i;
    ++next;
  }
  return -1;
}

namespace {

std::string direction_problem(const std::vector<double>& knots, int degree, const std::vector<double>& sites,
                              bool along_u, const Parameters& params) {
  const int gap = schoenberg_whitney_gap(knots, degree, sites);
  if (gap < 0) return "";
  const int count = static_cast<int>(knots.size()) - degree - 1;
  const char* axis = along_u ? "u" : "v";
  const double a = knots[static_cast<size_t>(gap)], b = knots[static_cast<size_t>(gap + degree + 1)];
  char where[160];
  if (params.kind == Parameterization::kTableXy) {
    const double lo = along_u ? params.x_min : params.y_min, hi = along_u ? params.x_max : params.y_max;
    std::snprintf(where, sizeof where, "%s %.3f..%.3f mm", along_u ? "x" : "y", lo + (hi - lo) * a, lo + (hi - lo) * b);
  } else {
    std::snprintf(where, sizeof where, "%s %.4f..%.4f", axis, a, b);
  }
  return std::to_string(count) + " control points along " + axis + " need as many distinct " +
         (along_u ? "positions" : "scan lines or positions") + " spread over their supports; the data has " +
         std::to_string(sites.size()) + " and none is left for control point " + std::to_string(gap) + " (" + where + ")";
}

// Kuhn's augmenting path from control point c; points visited in this search carry `stamp`.
bool augment(int c, const std::vector<std::vector<int>>& points_of, std::vector<int>& control_of_point,
             std::vector<int>& seen, int stamp) {
  for (int k : points_of[static_cast<size_t>(c)]) {
    if (seen[static_cast<size_t>(k)] == stamp) continue;
    seen[static_cast<size_t>(k)] = stamp;
    const int holder = control_of_point[static_cast<size_t>(k)];
    if (holder < 0 || augment(holder, points_of, control_of_point, seen, stamp)) {
      control_of_point[static_cast<size_t>(k)] = c;
      return true;
    }
  }
  return false;
}

}  // namespace

namespace {

// Whether point k lies under control point (i, j) with N_i(u) N_j(v) > min_product.
bool under(const std::vector<double>& knots_u, int degree_u, int count_u, const std::vector<double>& knots_v,
           int degree_v, int count_v, const UV& p, int i, int j, double min_product) {
  const int su = fit::find_span(count_u, degree_u, p.u, knots_u.data());
  const int a = i - (su - degree_u);
  if (a < 0 || a > degree_u) return false;
  const int sv = fit::find_span(count_v, degree_v, p.v, knots_v.data());
  const int b = j - (sv - degree_v);
  if (b < 0 || b > degree_v) return false;
  double nu[fit::kMaxDegree + 1], nv[fit::kMaxDegree + 1];
  fit::bspline_basis(su, degree_u, p.u, knots_u.data(), nu);
  fit::bspline_basis(sv, degree_v, p.v, knots_v.data(), nv);
  return nu[a] * nv[b] > min_product;
}

}  // namespace

std::pair<int, int> unmatched_control_point(const std::vector<double>& knots_u, int degree_u,
                                            const std::vector<double>& knots_v, int degree_v, const SiteIndex& index,
                                            double min_product, const std::vector<char>* outside) {
  const int count_u = static_cast<int>(knots_u.size()) - degree_u - 1;
  const int count_v = static_cast<int>(knots_v.size()) - degree_v - 1;
  if (count_u <= 0 || count_v <= 0 || degree_u > fit::kMaxDegree || degree_v > fit::kMaxDegree) return {-1, -1};
  const std::vector<UV>& uv = index.uv();
  std::vector<bool> ramp_u(static_cast<size_t>(count_u), false), ramp_v(static_cast<size_t>(count_v), false);
  for (const RampPoint& r : ramp_points(knots_u, degree_u, index.sites_u())) ramp_u[r.index] = true;
  for (const RampPoint& r : ramp_points(knots_v, degree_v, index.sites_v())) ramp_v[r.index] = true;
  // Each control point keeps at most `cap` of its points, one more than the other control points
  // whose supports overlap its own. That loses no matching: take one of the whole graph; the control
  // points with fewer than `cap` points keep all of theirs and their matches, and each of the others
  // then finds a free point among its `cap`, since only its cap - 1 neighbours can hold any of them.
  // So a million points cost a few dozen basis evaluations per control point, not a pass over all.
  const size_t cap = static_cast<size_t>(2 * degree_u + 1) * static_cast<size_t>(2 * degree_v + 1);
  std::vector<std::vector<int>> points_of(static_cast<size_t>(count_u) * count_v);
  auto asked = [&](int i, int j) {
    return !ramp_u[static_cast<size_t>(i)] && !ramp_v[static_cast<size_t>(j)] &&
           !(outside && (*outside)[static_cast<size_t>(i * count_v + j)]);
  };
  for (int i = 0; i < count_u; ++i) {
    for (int j = 0; j < count_v; ++j) {
      if (!asked(i, j)) continue;
      std::vector<int>& mine = points_of[static_cast<size_t>(i * count_v + j)];
      index.visit(knots_u[static_cast<size_t>(i)], knots_u[static_cast<size_t>(i + degree_u + 1)],
                  knots_v[static_cast<size_t>(j)], knots_v[static_cast<size_t>(j + degree_v + 1)], [&](size_t k) {
                    if (under(knots_u, degree_u, count_u, knots_v, degree_v, count_v, uv[k], i, j, min_product)) {
                      mine.push_back(static_cast<int>(k));
                    }
                    return mine.size() < cap;
                  });
    }
  }
  // The matching's points numbered by their place among those the lists hold (at most `cap` a
  // control point): arrays over every point of the index were two fills of the whole cloud per
  // call, and the tolerance loop calls this for every fold and every knot it would add.
  std::vector<int> held;
  for (const std::vector<int>& mine : points_of) held.insert(held.end(), mine.begin(), mine.end());
  std::sort(held.begin(), held.end());
  held.erase(std::unique(held.begin(), held.end()), held.end());
  for (std::vector<int>& mine : points_of) {
    for (int& k : mine) k = static_cast<int>(std::lower_bound(held.begin(), held.end(), k) - held.begin());
  }
  std::vector<int> control_of_point(held.size(), -1), seen(held.size(), -1);
  for (int i = 0; i < count_u; ++i) {
    for (int j = 0; j < count_v; ++j) {
      if (!asked(i, j)) continue;
      const int c = i * count_v + j;
      if (!augment(c, points_of, control_of_point, seen, c)) return {i, j};
    }
  }
  return {-1, -1};
}

std::vector<char> outside_control_points(const std::vector<double>& knots_u, int degree_u,
                                         const std::vector<double>& knots_v, int degree_v, const SiteIndex& index,
                                         double min_product) {
  const int count_u = static_cast<int>(knots_u.size()) - degree_u - 1;
  const int count_v = static_cast<int>(knots_v.size()) - degree_v - 1;
  if (count_u <= 0 || count_v <= 0 || degree_u > fit::kMaxDegree || degree_v > fit::kMaxDegree) return {};
  const std::vector<UV>& uv = index.uv();
  std::vector<char> outside(static_cast<size_t>(count_u) * count_v, 1);
  for (int i = 0; i < count_u; ++i) {
    for (int j = 0; j < count_v; ++j) {
      char& flag = outside[static_cast<size_t>(i * count_v + j)];
      index.visit(knots_u[static_cast<size_t>(i)], knots_u[static_cast<size_t>(i + degree_u + 1)],
                  knots_v[static_cast<size_t>(j)], knots_v[static_cast<size_t>(j + degree_v + 1)], [&](size_t k) {
                    if (under(knots_u, degree_u, count_u, knots_v, degree_v, count_v, uv[k], i, j, min_product)) flag = 0;
                    return flag != 0;
                  });
    }
  }
  return outside;
}

std::string net_support_problem(const std::vector<double>& knots_u, int degree_u, const std::vector<double>& knots_v,
                                int degree_v, const SiteIndex& index, const Parameters& params,
                                const std::vector<char>* outside) {
  if (outside) {
    const auto [i, j] = unmatched_control_point(knots_u, degree_u, knots_v, degree_v, index, 0.0, outside);
    if (i < 0) return "";
    return "control point (" + std::to_string(i) + ", " + std::to_string(j) +
           ") has no point of its own under its support (the region is too small or too thin for this net)";
  }
  std::string problem = direction_problem(knots_u, degree_u, index.sites_u(), true, params);
  if (problem.empty()) problem = direction_problem(knots_v, degree_v, index.sites_v(), false, params);
  return problem;
}

}  // namespace dg::host
