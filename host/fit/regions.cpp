// Segmenting a scan at creases and steps, fitting each region, and trimming the surfaces where they meet.
#include "host/fit/regions.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include "host/fit/bspline_fit.h"
#include "host/fit/fit_error.h"
#include "host/fit/noise_estimate.h"
#include "host/fit/parameterize.h"
#include "host/geometry/closest_point.h"
#include "host/parallel/parallel_for.h"
#include "host/scan/local_polynomial.h"
#include "host/scan/median.h"
#include "host/scan/neighbours.h"

namespace dg::host {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr size_t kJoined = 5;
constexpr double kBoundaryShare = 0.9;

std::string mm_text(double mm) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4f mm", mm);
  return text;
}

struct Box {
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  bool contains(double x, double y) const {
    const double e = 1e-9 * (1 + std::fabs(x1 - x0) + std::fabs(y1 - y0));
    return x >= x0 - e && x <= x1 + e && y >= y0 - e && y <= y1 + e;
  }
  // Table XY parameters over the box (its points' uv still to add) and a point's uv in it.
  Parameters parameters() const {
    Parameters params;
    params.kind = Parameterization::kTableXy;
    params.x_min = x0;
    params.x_max = x1;
    params.y_min = y0;
    params.y_max = y1;
    return params;
  }
  UV uv(const Point3& p) const {
    return {std::clamp((p.x - x0) / (x1 - x0), 0.0, 1.0), std::clamp((p.y - y0) / (y1 - y0), 0.0, 1.0)};
  }
};

// A region while it is built: its points, its box and its surface.
struct Region {
  std::vector<size_t> core, members;
  Box box;
  BSplineSurface surface;
  bool fitted = false;
  RegionReport report;
  double z_at(double x, double y) const {
    double u, v;
    table_to_parameters(surface, x, y, u, v);
    return surface.evaluate(u, v).z;
  }
};

// The median distance from a point to its nearest neighbour in XY: the scan's step.
double scan_step(const std::vector<Point3>& points, const Neighbourhoods& near) {
  if (near.k < 2) return 0;
  std::vector<double> d;
  for (size_t i = 0; i < points.size(); ++i) {
    const Point3& q = points[near.list(i)[1]];
    d.push_back(std::hypot(q.x - points[i].x, q.y - points[i].y));
  }
  if (d.empty()) return 0;
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

// A region's fit: the asked tolerance at `degree`, from one patch, control points beyond its points placed.
ToleranceOptions region_options(const RegionOptions& options, int degree) {
  ToleranceOptions o = options.tolerance;
  o.degree_u = o.degree_v = degree;
  o.start_count_u = o.start_count_v = 0;
  o.extra_knots_u.clear();
  o.extra_knots_v.clear();
  o.fill_outside = true;
  return o;
}

// Fits one region's points over its box; the region's report says what became of it.
void fit_region(const PointCloud& cloud, const std::vector<double>* weights, const RegionOptions& options, Region& r) {
  PointCloud sub;
  std::vector<double> sub_weights;
  std::vector<uint32_t> lines;
  for (size_t i : r.members) {
    sub.points.push_back(cloud.points[i]);
    if (cloud.line) lines.push_back((*cloud.line)[i]);
    if (weights) sub_weights.push_back((*weights)[i]);
  }
  if (cloud.line) sub.line = lines;
  sub.resolution_mm = cloud.resolution_mm;
  Parameters params = r.box.parameters();
  for (const Point3& p : sub.points) params.uv.push_back(r.box.uv(p));
  r.report.points = r.members.size();
  // The simplest surface that keeps the tolerance: a single bilinear, then biquadratic patch is
  // tried before the refined net of the asked degree. A flat piece of base plate stays a plane,
  // which extrapolates to its trim far better than a curved patch fitted to its noise.
  for (int degree = 1; degree < options.tolerance.degree_u; ++degree) {
    if (r.members.size() < static_cast<size_t>(3 * (degree + 1) * (degree + 1))) break;
    ToleranceOptions o = region_options(options, degree);
    o.max_iterations = 1;
    try {
      ToleranceResult t = fit_to_tolerance(sub, params, weights ? &sub_weights : nullptr, o);
      if (!t.kept) continue;
      r.surface = std::move(t.surface);
      r.fitted = true;
      r.report.kept = true;
      r.report.reason.clear();
      r.report.validation = t.validation;
      return;
    } catch (const FitError&) {
      // Not determined at this degree: the next one decides.
    }
  }
  // A small region cannot carry a cubic net: the degree drops until its points determine one.
  std::string last_error = "too few points";
  for (int degree = options.tolerance.degree_u; degree >= 1; --degree) {
    if (r.members.size() < static_cast<size_t>(3 * (degree + 1) * (degree + 1)) && degree > 1) continue;
    const ToleranceOptions o = region_options(options, degree);
    try {
      ToleranceResult t = fit_to_tolerance(sub, params, weights ? &sub_weights : nullptr, o);
      r.surface = std::move(t.surface);
      r.fitted = true;
      r.report.kept = t.kept;
      r.report.reason = t.reason;
      r.report.validation = t.validation;
      return;
    } catch (const FitError& e) {
      last_error = e.what();
    }
  }
  r.fitted = false;
  r.report.kept = false;
  r.report.reason = "its " + std::to_string(r.members.size()) + " points cannot carry a surface: " + last_error;
}

// The surface near a region's trim rests on its outermost points. They are held out in two folds
// (alternate points along the boundary, so each refit keeps the other half and the net stays
// determined there) and must be predicted within the tolerance; a region that fails is not kept.
void check_boundary(const PointCloud& cloud, const std::vector<double>* weights, const Neighbourhoods& near,
                    const std::vector<int>& owner, double step, double tol, int id, Region& r) {
  std::vector<size_t> outer;
  std::vector<char> is_outer(r.members.size(), 0);
  for (size_t m = 0; m < r.members.size(); ++m) {
    const size_t i = r.members[m];
    for (size_t j : near.list(i)) {
      const Point3& a = cloud.points[i];
      const Point3& b = cloud.points[j];
      if (owner[j] != id && std::hypot(a.x - b.x, a.y - b.y) <= 1.5 * step) is_outer[m] = 1;
    }
  }
  LsqSpec spec;
  spec.degree_u = r.surface.degree_u;
  spec.degree_v = r.surface.degree_v;
  spec.knots_u = r.surface.knots_u;
  spec.knots_v = r.surface.knots_v;
  spec.fill_outside = true;
  double worst = 0;
  size_t worst_i = 0, held = 0;
  for (int fold = 0; fold < 2; ++fold) {
    std::vector<Point3> kept;
    std::vector<double> kept_weights;
    std::vector<size_t> out;
    Parameters params = r.box.parameters();
    for (size_t m = 0; m < r.members.size(); ++m) {
      const size_t i = r.members[m];
      const Point3& p = cloud.points[i];
      // Alternate points: the parity of the grid position along the boundary.
      const long parity = (std::lround(p.x / step) + std::lround(p.y / step)) & 1;
      if (is_outer[m] && parity == fold) {
        out.push_back(i);
        continue;
      }
      kept.push_back(p);
      if (weights) kept_weights.push_back((*weights)[i]);
      params.uv.push_back(r.box.uv(p));
    }
    if (out.empty()) continue;
    BSplineSurface refit;
    try {
      refit = fit_least_squares(kept, params, weights ? &kept_weights : nullptr, spec);
    } catch (const FitError& e) {
      r.report.kept = false;
      r.report.reason = "its surface cannot be checked at its boundary: without half of its " +
                        std::to_string(std::count(is_outer.begin(), is_outer.end(), 1)) + " outermost points " + e.what();
      return;
    }
    for (size_t i : out) {
      const Point3& p = cloud.points[i];
      double u, v;
      table_to_parameters(refit, p.x, p.y, u, v);
      double d = std::fabs(p.z - refit.evaluate(u, v).z);
      if (d > tol) d = std::fabs(closest_point(refit, p, u, v).distance);
      if (d >= worst) worst = d, worst_i = i;
      ++held;
    }
  }
  r.report.boundary_points = held;
  r.report.boundary_max_mm = worst;
  // The trim lies up to a step beyond these points, where the surface is extrapolated: a tenth of
  // the tolerance is held back for that (a margin found on the simulated dome, not a bound).
  if (worst > kBoundaryShare * tol) {
    const Point3& p = cloud.points[worst_i];
    char where[96];
    std::snprintf(where, sizeof where, "(%.3f, %.3f, %.3f)", p.x, p.y, p.z);
    r.report.kept = false;
    r.report.reason = "its surface is not trusted at its boundary: fitted without it, the outermost point " +
                      std::string(where) + " is missed by " + mm_text(worst) + " > 0.9 x tolerance " + mm_text(tol) +
                      " (scan finer across the crease or give a larger tolerance)";
  }
}

// Points in buckets of a square grid over the scan, for nearest-point searches.
class Buckets {
 public:
  Buckets(const std::vector<Point3>& points, const Box& box, double cell) : points_(points), box_(box), cell_(cell) {
    nx_ = std::max(1, static_cast<int>((box.x1 - box.x0) / cell) + 1);
    ny_ = std::max(1, static_cast<int>((box.y1 - box.y0) / cell) + 1);
    cells_.resize(static_cast<size_t>(nx_) * ny_);
  }
  void add(size_t i) { cells_[index(points_[i].x, points_[i].y)].push_back(i); }
  // Calls visit(i, distance) for every point within `reach` of (x, y).
  template <class Visit>
  void within(double x, double y, double reach, Visit visit) const {
    const int cx = cell_x(x), cy = cell_y(y), n = static_cast<int>(std::ceil(reach / cell_));
    for (int a = std::max(0, cx - n); a <= std::min(nx_ - 1, cx + n); ++a) {
      for (int b = std::max(0, cy - n); b <= std::min(ny_ - 1, cy + n); ++b) {
        for (size_t i : cells_[static_cast<size_t>(a) * ny_ + b]) {
          const double d = std::hypot(points_[i].x - x, points_[i].y - y);
          if (d <= reach) visit(i, d);
        }
      }
    }
  }

 private:
  int cell_x(double x) const { return std::clamp(static_cast<int>((x - box_.x0) / cell_), 0, nx_ - 1); }
  int cell_y(double y) const { return std::clamp(static_cast<int>((y - box_.y0) / cell_), 0, ny_ - 1); }
  size_t index(double x, double y) const { return static_cast<size_t>(cell_x(x)) * ny_ + cell_y(y); }
  const std::vector<Point3>& points_;
  Box box_;
  double cell_;
  int nx_ = 1, ny_ = 1;
  std::vector<std::vector<size_t>> cells_;
};

// Douglas-Peucker on a closed loop: vertices within `eps` of the chord between kept ones go.
void simplify_chain(const TrimLoop& in, size_t a, size_t b, double eps, std::vector<char>& keep) {
  if (b <= a + 1) return;
  const Point2& p = in[a];
  const Point2& q = in[b % in.size()];
  const double dx = q.x - p.x, dy = q.y - p.y, len = std::hypot(dx, dy);
  double worst = -1;
  size_t at = a;
  for (size_t k = a + 1; k < b; ++k) {
    const double d = len > 0 ? std::fabs((in[k].x - p.x) * dy - (in[k].y - p.y) * dx) / len
                             : std::hypot(in[k].x - p.x, in[k].y - p.y);
    if (d > worst) worst = d, at = k;
  }
  if (worst <= eps) return;
  keep[at] = 1;
  simplify_chain(in, a, at, eps, keep);
  simplify_chain(in, at, b, eps, keep);
}

TrimLoop simplify_loop(const TrimLoop& in, double eps) {
  if (in.size() < 8) return in;
  size_t far = 0;
  double far_d = -1;
  for (size_t k = 1; k < in.size(); ++k) {
    const double d = std::hypot(in[k].x - in[0].x, in[k].y - in[0].y);
    if (d > far_d) far_d = d, far = k;
  }
  std::vector<char> keep(in.size(), 0);
  keep[0] = keep[far] = 1;
  simplify_chain(in, 0, far, eps, keep);
  simplify_chain(in, far, in.size(), eps, keep);
  TrimLoop out;
  for (size_t k = 0; k < in.size(); ++k) {
    if (keep[k]) out.push_back(in[k]);
  }
  return out;
}

}  // namespace

RegionFit fit_regions(const PointCloud& cloud, const std::vector<double>* weights, const RegionOptions& options) {
  RegionFit out;
  const std::vector<Point3>& pts = cloud.points;
  const size_t n = pts.size();
  if (n < static_cast<size_t>(options.neighbours)) return out;
  const Parameters table = parameterize(cloud, Parameterization::kTableXy);
  const NoiseEstimate noise = estimate_gauge_noise(cloud, table);
  out.noise_sigma_mm = noise.sigma_mm;
  const double sigma = noise.reading_sigma_mm;
  const double tol = options.tolerance.tolerance_mm;
  // In one array, in the buckets' order: copying each point's list into a vector of its own added a
  // quarter to the search's time on a million scattered points, and 68 MB to the peak of
  // `fit --tolerance` (326 MB against 258).
  const Neighbourhoods near = nearest_neighbours(pts, static_cast<size_t>(options.neighbours));
  const double step = scan_step(pts, near);
  if (!(step > 0)) return out;

  // 1. Smooth windows: a quadratic holds the neighbourhood to the noise. A window across a crease or
  // step never does, so the points that share a smooth window lie on one smooth piece; a point
  // beside a crease still belongs to the windows on its own side of it.
  std::vector<size_t> parent(n);
  for (size_t i = 0; i < n; ++i) parent[i] = i;
  auto find = [&](size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::vector<char> smooth(n, 0), smooth_window(n, 0);
  const double smooth_rms = std::max(3.0 * sigma, 0.25 * tol);
  // Whether a quadratic holds these points to the noise (RMS over the points less its 6 terms).
  auto smooth_over = [&](const std::vector<size_t>& window, const Point3& centre) {
    LocalPolynomial lp;
    if (!fit_local_polynomial(pts, window, centre, 2, lp)) return false;
    double sum = 0;
    for (size_t k : window) sum += (pts[k].z - lp.at(pts[k].x, pts[k].y)) * (pts[k].z - lp.at(pts[k].x, pts[k].y));
    return std::sqrt(sum / static_cast<double>(window.size() - 6)) <= smooth_rms;
  };
  // Each window on its own, on every core (a million scattered points: 0.56 s on one), taken in the
  // buckets' order so that neighbouring windows share what the cache holds; the joins after, in
  // point order.
  parallel_for(n, [&](size_t begin, size_t end, unsigned) {
    std::vector<size_t> window;
    for (size_t position = begin; position < end; ++position) {
      const Neighbourhoods::List list = near.list_at_position(position);
      const size_t i = near.order[position];
      window.assign(list.begin(), list.end());
      smooth_window[i] = window.size() >= 10 && smooth_over(window, pts[i]);
    }
  }, 1024);
  for (size_t i = 0; i < n; ++i) {
    if (!smooth_window[i]) continue;
    // Only the window's centre and its four nearest join: a point at its rim may lie where two
    // pieces meet and belong to both (where a crease runs out at the scan's edge, say).
    for (size_t m = 0; m < near.k && m < kJoined; ++m) {
      const size_t k = near.list(i)[m];
      smooth[k] = 1;
      parent[find(k)] = find(i);
    }
  }
  // Two neighbours whose smooth windows one quadratic also holds together, to the same noise, lie
  // on one piece: across a crease the two windows' union straddles it and no quadratic holds it.
  // This joins what the centres' four nearest miss among scattered points, whose nearest-neighbour
  // links leave small islands of a few points: on a million points of a smooth part they had made
  // 13 "regions" and a refused fit. Asked only of neighbours not yet joined, so it costs little.
  auto holds_both = [&](size_t i, size_t j) {
    const Neighbourhoods::List around_i = near.list(i);
    std::vector<size_t> both(around_i.begin(), around_i.end());
    for (size_t k : near.list(j)) {
      if (std::find(around_i.begin(), around_i.end(), k) == around_i.end()) both.push_back(k);
    }
    return smooth_over(both, pts[i]);
  };
  for (size_t i = 0; i < n; ++i) {
    if (!smooth_window[i]) continue;
    for (size_t j : near.list(i)) {
      if (j == i || !smooth_window[j] || find(i) == find(j)) continue;
      if (holds_both(i, j)) parent[find(j)] = find(i);
    }
  }
  // 2. The pieces: smooth points joined through shared windows.
  std::vector<int> region_of(n, -1);
  std::vector<Region> regions;
  {
    std::map<size_t, int> id_of_root;
    for (size_t i = 0; i < n; ++i) {
      if (!smooth[i]) continue;
      const size_t root = find(i);
      auto it = id_of_root.find(root);
      if (it == id_of_root.end()) {
        it = id_of_root.emplace(root, static_cast<int>(regions.size())).first;
        regions.emplace_back();
      }
      regions[static_cast<size_t>(it->second)].core.push_back(i);
    }
  }
  // Small regions (a few smooth points amid a crease) are not regions: their points are crease points.
  std::vector<Region> kept_regions;
  for (Region& r : regions) {
    if (r.core.size() >= options.min_region_points) kept_regions.push_back(std::move(r));
  }
  regions = std::move(kept_regions);
  std::fill(region_of.begin(), region_of.end(), -1);
  for (size_t id = 0; id < regions.size(); ++id) {
    for (size_t i : regions[id].core) region_of[i] = static_cast<int>(id);
  }
  out.regions = static_cast<int>(regions.size());
  out.crease_points = static_cast<size_t>(std::count(region_of.begin(), region_of.end(), -1));
  if (regions.size() < 2) return out;

  Box scan{table.x_min, table.x_max, table.y_min, table.y_max};
  const double margin = 4 * step;
  auto set_box = [&](Region& r) {
    Box b{kInf, -kInf, kInf, -kInf};
    for (size_t i : r.members) {
      b.x0 = std::min(b.x0, pts[i].x), b.x1 = std::max(b.x1, pts[i].x);
      b.y0 = std::min(b.y0, pts[i].y), b.y1 = std::max(b.y1, pts[i].y);
    }
    r.box = {std::max(scan.x0, b.x0 - margin), std::min(scan.x1, b.x1 + margin), std::max(scan.y0, b.y0 - margin),
             std::min(scan.y1, b.y1 + margin)};
  };
  // 3. Fit the cores; the crease points join the region whose surface passes nearest, within the
  // tolerance; fit again with them (twice, so a point can move to the surface that now fits it).
  for (Region& r : regions) {
    r.members = r.core;
    set_box(r);
    fit_region(cloud, weights, options, r);
  }
  Buckets core_buckets(pts, scan, 2 * step);
  for (size_t id = 0; id < regions.size(); ++id) {
    for (size_t i : regions[id].core) core_buckets.add(i);
  }
  for (int round = 0; round < 2; ++round) {
    for (Region& r : regions) r.members = r.core;
    for (size_t i = 0; i < n; ++i) {
      if (region_of[i] >= 0) continue;
      std::vector<char> close(regions.size(), 0);
      core_buckets.within(pts[i].x, pts[i].y, margin, [&](size_t k, double) { close[static_cast<size_t>(region_of[k])] = 1; });
      int best = -1;
      double best_d = tol;
      for (size_t id = 0; id < regions.size(); ++id) {
        const Region& r = regions[id];
        if (!close[id] || !r.fitted || !r.box.contains(pts[i].x, pts[i].y)) continue;
        const double d = std::fabs(pts[i].z - r.z_at(pts[i].x, pts[i].y));
        if (d <= best_d) best_d = d, best = static_cast<int>(id);
      }
      if (best >= 0) regions[static_cast<size_t>(best)].members.push_back(i);
    }
    for (Region& r : regions) {
      std::sort(r.members.begin(), r.members.end());  // scan order, so lines stay whole for the folds
      set_box(r);
      fit_region(cloud, weights, options, r);
    }
  }
  std::vector<int> owner(n, -1);
  for (size_t id = 0; id < regions.size(); ++id) {
    for (size_t i : regions[id].members) owner[i] = static_cast<int>(id);
    regions[id].report.core_points = regions[id].core.size();
  }
  out.unassigned_points = static_cast<size_t>(std::count(owner.begin(), owner.end(), -1));
  for (size_t id = 0; id < regions.size(); ++id) {
    if (regions[id].fitted && regions[id].report.kept) check_boundary(cloud, weights, near, owner, step, tol, static_cast<int>(id), regions[id]);
  }
  for (const Region& r : regions) out.reports.push_back(r.report);
  for (size_t id = 0; id < regions.size(); ++id) {
    if (!regions[id].fitted) {
      out.reason = "region " + std::to_string(id + 1) + ": " + regions[id].report.reason;
      return out;
    }
  }

  // 4. Which surfaces cross between their regions (a crease) and on which side each is on top.
  const size_t rc = regions.size();
  // Only the points right beside the other region vote: farther away a surface is extrapolated.
  std::vector<int> side(rc * rc, 0);  // side[a * rc + b]: sign of s_a - s_b on a's points beside b
  Buckets member_buckets(pts, scan, 2 * step);
  for (size_t i = 0; i < n; ++i) {
    if (owner[i] >= 0) member_buckets.add(i);
  }
  {
    std::vector<int> votes(rc * rc, 0), counts(rc * rc, 0);
    for (size_t i = 0; i < n; ++i) {
      const int a = owner[i];
      if (a < 0) continue;
      std::vector<char> close(rc, 0);
      member_buckets.within(pts[i].x, pts[i].y, 1.5 * step, [&](size_t k, double) { close[static_cast<size_t>(owner[k])] = 1; });
      for (size_t b = 0; b < rc; ++b) {
        if (b == static_cast<size_t>(a) || !close[b] || !regions[b].box.contains(pts[i].x, pts[i].y)) continue;
        const double d = regions[static_cast<size_t>(a)].z_at(pts[i].x, pts[i].y) - regions[b].z_at(pts[i].x, pts[i].y);
        votes[static_cast<size_t>(a) * rc + b] += d > 0 ? 1 : -1;
        ++counts[static_cast<size_t>(a) * rc + b];
      }
    }
    for (size_t a = 0; a < rc; ++a) {
      for (size_t b = 0; b < rc; ++b) {
        const int va = votes[a * rc + b], vb = votes[b * rc + a];
        // A crease when on each side, clearly (two to one), that side's surface is the upper one (a
        // ridge, max) or on each side the lower (a valley, min): s_a - s_b changes sign between them.
        const bool a_clear = std::abs(va) * 3 > counts[a * rc + b] * 2, b_clear = std::abs(vb) * 3 > counts[b * rc + a] * 2;
        if (a_clear && b_clear && (va > 0) == (vb > 0)) side[a * rc + b] = va > 0 ? 1 : -1;
      }
    }
  }

  // 5. Label a fine grid over the scan with the region whose face covers each node.
  const double area = (scan.x1 - scan.x0) * (scan.y1 - scan.y0);
  const double g = std::max(step / 4, std::sqrt(area / 4e6));
  const int nx = static_cast<int>(std::ceil((scan.x1 - scan.x0) / g)) + 1;
  const int ny = static_cast<int>(std::ceil((scan.y1 - scan.y0) / g)) + 1;
  const double gx = (scan.x1 - scan.x0) / (nx - 1), gy = (scan.y1 - scan.y0) / (ny - 1);
  auto node_x = [&](int i) { return i == nx - 1 ? scan.x1 : scan.x0 + i * gx; };
  auto node_y = [&](int j) { return j == ny - 1 ? scan.y1 : scan.y0 + j * gy; };
  std::vector<int> label(static_cast<size_t>(nx) * ny, -1);
  const double reach = 6 * step;
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      const double x = node_x(i), y = node_y(j);
      std::vector<double> dist(rc, kInf);
      member_buckets.within(x, y, reach, [&](size_t k, double d) {
        double& best = dist[static_cast<size_t>(owner[k])];
        best = std::min(best, d);
      });
      int a = -1;
      for (size_t r = 0; r < rc; ++r) {
        if (dist[r] < kInf && regions[r].box.contains(x, y) && (a < 0 || dist[r] < dist[static_cast<size_t>(a)])) a = static_cast<int>(r);
      }
      if (a < 0) {
        char where[96];
        std::snprintf(where, sizeof where, "(%.3f, %.3f)", x, y);
        out.reason = std::string("no region's points lie within ") + mm_text(reach) + " of " + where +
                     ": the regions leave a gap in the scan there";
        return out;
      }
      for (size_t b = 0; b < rc; ++b) {
        if (static_cast<int>(b) == a || dist[b] > dist[static_cast<size_t>(a)] + 4 * step) continue;
        const int s = side[static_cast<size_t>(a) * rc + b];
        if (s == 0 || !regions[b].box.contains(x, y)) continue;
        const double d = regions[static_cast<size_t>(a)].z_at(x, y) - regions[b].z_at(x, y);
        if ((d > 0 ? 1 : -1) != s) {
          a = static_cast<int>(b);
          break;
        }
      }
      label[static_cast<size_t>(i) * ny + j] = a;
    }
  }

  // 6. Each region's boundary: marching squares on its label, the vertex on each cut grid edge at
  // the surfaces' intersection (a crease) or midway (a step), and on the scan's edge at the edge.
  for (size_t id = 0; id < rc; ++id) {
    auto in = [&](int i, int j) {
      return i >= 0 && j >= 0 && i < nx && j < ny && label[static_cast<size_t>(i) * ny + j] == static_cast<int>(id);
    };
    // Edges are numbered on the grid padded by one node: horizontal (i, j)-(i+1, j) and vertical.
    auto edge_id = [&](int i, int j, bool horizontal) { return ((static_cast<long>(i + 1) * (ny + 2) + (j + 1)) << 1) | (horizontal ? 1 : 0); };
    auto edge_point = [&](int i1, int j1, int i2, int j2) {
      // (i1, j1) inside, (i2, j2) outside or beyond the grid.
      const double x1 = node_x(i1), y1 = node_y(j1);
      if (i2 < 0 || j2 < 0 || i2 >= nx || j2 >= ny) return Point2{x1, y1};
      const double x2 = node_x(i2), y2 = node_y(j2);
      const int b = label[static_cast<size_t>(i2) * ny + j2];
      double t = 0.5;
      if (b >= 0 && side[id * rc + static_cast<size_t>(b)] != 0 && regions[static_cast<size_t>(b)].box.contains(x1, y1) &&
          regions[id].box.contains(x2, y2)) {
        // From the lower-numbered region's side, so both faces get the very same vertex.
        const bool mine = id < static_cast<size_t>(b);
        const Region& lo = mine ? regions[id] : regions[static_cast<size_t>(b)];
        const Region& hi = mine ? regions[static_cast<size_t>(b)] : regions[id];
        const double d1 = lo.z_at(x1, y1) - hi.z_at(x1, y1), d2 = lo.z_at(x2, y2) - hi.z_at(x2, y2);
        if (d1 * d2 < 0) t = d1 / (d1 - d2);
      }
      return Point2{x1 + t * (x2 - x1), y1 + t * (y2 - y1)};
    };
    std::map<long, std::pair<long, Point2>> next;  // from edge: (to edge, the start edge's point)
    for (int i = -1; i < nx; ++i) {
      for (int j = -1; j < ny; ++j) {
        // Corners counter-clockwise: (i, j), (i+1, j), (i+1, j+1), (i, j+1).
        const int ci[4] = {i, i + 1, i + 1, i}, cj[4] = {j, j, j + 1, j + 1};
        bool c[4];
        for (int k = 0; k < 4; ++k) c[k] = in(ci[k], cj[k]);
        if (c[0] == c[1] && c[1] == c[2] && c[2] == c[3]) continue;
        const long e[4] = {edge_id(i, j, true), edge_id(i + 1, j, false), edge_id(i, j + 1, true), edge_id(i, j, false)};
        for (int k = 0; k < 4; ++k) {
          const int k1 = (k + 1) % 4;
          if (!(c[k] && !c[k1])) continue;  // edge k leaves the region: a segment starts here
          int m = (k + 3) % 4;
          while (!(!c[m] && c[(m + 1) % 4])) m = (m + 3) % 4;  // the edge that entered around corner k
          const Point2 start = c[k] ? edge_point(ci[k], cj[k], ci[k1], cj[k1]) : Point2{};
          next[e[k]] = {e[m], start};
        }
      }
    }
    std::vector<TrimLoop> loops;
    while (!next.empty()) {
      TrimLoop loop;
      long at = next.begin()->first;
      while (true) {
        auto it = next.find(at);
        if (it == next.end()) break;
        loop.push_back(it->second.second);
        at = it->second.first;
        next.erase(it);
      }
      TrimLoop simple = simplify_loop(loop, 1e-3);
      if (simple.size() >= 3 && std::fabs(twice_signed_area(simple)) > 0) loops.push_back(std::move(simple));
    }
    // Counter-clockwise loops bound pieces of the region; clockwise ones are holes in the piece around them.
    std::vector<TrimLoop> outers, holes;
    for (TrimLoop& l : loops) (twice_signed_area(l) > 0 ? outers : holes).push_back(std::move(l));
    std::sort(outers.begin(), outers.end(),
              [](const TrimLoop& a, const TrimLoop& b) { return twice_signed_area(a) > twice_signed_area(b); });
    const size_t first_face = out.faces.size();
    for (TrimLoop& o : outers) {
      TrimmedFace f;
      f.surface = regions[id].surface;
      f.loops.push_back(std::move(o));
      out.faces.push_back(std::move(f));
      out.face_region.push_back(static_cast<int>(id));
    }
    for (TrimLoop& h : holes) {
      for (size_t k = out.faces.size(); k-- > first_face;) {
        if (inside_loop(out.faces[k].loops[0], h[0].x, h[0].y)) {
          out.faces[k].loops.push_back(std::move(h));
          break;
        }
      }
    }
  }

  // The faces' standard uncertainty, from the region's points and their noise (or sigma column).
  // With a sigma column the weights carry each point's own; the median is the figure stated.
  double sigma_u = sigma;
  if (weights) {
    std::vector<double> sigmas;
    for (double w : *weights) sigmas.push_back(1.0 / std::sqrt(w));
    sigma_u = median_of(sigmas);
  }
  for (size_t f = 0; f < out.faces.size() && sigma_u > 0; ++f) {
    TrimmedFace& face = out.faces[f];
    const Region& r = regions[static_cast<size_t>(out.face_region[f])];
    std::vector<Point3> points;
    std::vector<double> w;
    Parameters params = r.box.parameters();
    for (size_t i : r.members) {
      points.push_back(pts[i]);
      if (weights) w.push_back((*weights)[i]);
      params.uv.push_back(r.box.uv(pts[i]));
    }
    auto counts = [&](double u, double v) {
      return inside_face(face, r.box.x0 + u * (r.box.x1 - r.box.x0), r.box.y0 + v * (r.box.y1 - r.box.y0));
    };
    try {
      face.uncertainty = region_fit_uncertainty(points, params, weights ? &w : nullptr, face.surface, sigma_u, 41, counts);
      face.uncertainty.sigma_from = weights ? cloud.sigma_from + " (median)" : "noise estimate";
    } catch (const FitError&) {
      // The net cannot be refitted from these points: no uncertainty to state for this face.
    }
  }

  // 7. The contract on the whole: every point within the tolerance of the face above it.
  std::vector<std::vector<double>> face_distances(out.faces.size());
  out.distances.assign(n, 0.0);
  size_t worst_point = 0;
  for (size_t i = 0; i < n; ++i) {
    int face = -1;
    for (size_t f = 0; f < out.faces.size() && face < 0; ++f) {
      if (inside_face(out.faces[f], pts[i].x, pts[i].y)) face = static_cast<int>(f);
    }
    if (face < 0) {
      // On a boundary (even-odd cannot say): the face of the nearest grid node's label.
      const int gi = std::clamp(static_cast<int>(std::lround((pts[i].x - scan.x0) / gx)), 0, nx - 1);
      const int gj = std::clamp(static_cast<int>(std::lround((pts[i].y - scan.y0) / gy)), 0, ny - 1);
      const int r = label[static_cast<size_t>(gi) * ny + gj];
      for (size_t f = 0; f < out.faces.size() && face < 0; ++f) {
        if (out.face_region[f] == r) face = static_cast<int>(f);
      }
    }
    if (face < 0) continue;
    const BSplineSurface& s = out.faces[static_cast<size_t>(face)].surface;
    double u, v;
    table_to_parameters(s, pts[i].x, pts[i].y, u, v);
    double d = pts[i].z - s.evaluate(u, v).z;
    if (std::fabs(d) > 0.5 * tol) d = closest_point(s, pts[i], u, v).distance;
    face_distances[static_cast<size_t>(face)].push_back(d);
    out.distances[i] = d;
    if (std::fabs(d) > out.max_distance_mm) out.max_distance_mm = std::fabs(d), worst_point = i;
  }
  for (size_t f = 0; f < out.faces.size(); ++f) {
    out.faces[f].distance = distance_stats(face_distances[f]);
    out.faces[f].points = face_distances[f].size();
  }
  // The regions' validations as one: every fold of every region, the worst of each figure.
  FitValidation& v = out.validation;
  double held_sq = 0;
  for (const Region& r : regions) {
    const FitValidation& rv = r.report.validation;
    if (!rv.checked) continue;
    v.checked = true;
    v.folds = std::max(v.folds, rv.folds);
    v.folds_of_lines = rv.folds_of_lines;
    held_sq += rv.held_out_rms_mm * rv.held_out_rms_mm * static_cast<double>(rv.held_out_points);
    v.held_out_points += rv.held_out_points;
    if (rv.held_out_max_mm >= v.held_out_max_mm) v.held_out_max_mm = rv.held_out_max_mm, v.held_out_worst = rv.held_out_worst;
    v.neighbour_checks += rv.neighbour_checks;
    if (rv.range_excess_max_mm >= v.range_excess_max_mm) v.range_excess_max_mm = rv.range_excess_max_mm, v.range_worst = rv.range_worst;
    if (v.problem.empty()) v.problem = rv.problem;
  }
  if (v.held_out_points > 0) v.held_out_rms_mm = std::sqrt(held_sq / static_cast<double>(v.held_out_points));
  v.passed = v.checked && v.problem.empty();
  for (size_t id = 0; id < rc; ++id) {
    if (!regions[id].report.kept) {
      out.reason = "region " + std::to_string(id + 1) + " (" + std::to_string(regions[id].members.size()) +
                   " points): " + regions[id].report.reason;
      return out;
    }
  }
  if (out.max_distance_mm > tol) {
    const Point3& w = pts[worst_point];
    char where[96];
    std::snprintf(where, sizeof where, "(%.3f, %.3f, %.3f)", w.x, w.y, w.z);
    out.reason = std::string("the point ") + where + " lies " + mm_text(out.max_distance_mm) +
                 " from the trimmed face above it, beyond the tolerance " + mm_text(tol);
    return out;
  }
  out.kept = true;
  return out;
}

}  // namespace dg::host
