// Hold-out refits by fold and bounding-box checks between neighbouring samples.
#include "host/fit/fit_validation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>

#include "host/fit/bucket_sort.h"
#include "host/fit/fit_error.h"
#include "host/fit/knot_support.h"
#include "host/geometry/closest_point.h"
#include "host/geometry/curvature_bound.h"
#include "host/geometry/patch_form.h"
#include "host/parallel/parallel_for.h"
#include "host/scan/neighbours.h"
#include "host/scan/sorted_lines.h"

namespace dg::host {

namespace {

std::string mm(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4f mm", value);
  return text;
}

std::string at(const Point3& p) {
  char text[64];
  std::snprintf(text, sizeof text, "(%.3f, %.3f, %.3f)", p.x, p.y, p.z);
  return text;
}

// Points of each line in scan order, lines in id order.
std::vector<std::vector<size_t>> lines_of(const PointCloud& cloud) {
  std::map<uint32_t, std::vector<size_t>> by_id;
  for (size_t i = 0; i < cloud.points.size(); ++i) by_id[(*cloud.line)[i]].push_back(i);
  std::vector<std::vector<size_t>> lines;
  for (auto& [id, members] : by_id) lines.push_back(std::move(members));
  return lines;
}

// How far `s` lies outside the box of `corners` widened by `slack` (0 inside).
double box_excess(const Point3& s, const Point3* const* corners, int count, double slack) {
  Point3 lo = *corners[0], hi = *corners[0];
  for (int k = 1; k < count; ++k) {
    const Point3& c = *corners[k];
    lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
    hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
  }
  const double dx = std::max({lo.x - slack - s.x, s.x - hi.x - slack, 0.0});
  const double dy = std::max({lo.y - slack - s.y, s.y - hi.y - slack, 0.0});
  const double dz = std::max({lo.z - slack - s.z, s.z - hi.z - slack, 0.0});
  return std::max({dx, dy, dz});
}

// The checks of one unit of work (a scan line, a point): how many, and the worst.
struct RangeWorst {
  size_t checks = 0;
  double excess_mm = 0;
  Point3 where{};
  // A unit whose bound is below this (or below excess_mm) cannot be the worst: it is certified
  // instead of evaluated. Not merged.
  double floor_mm = 0;
  // Keeps the first of equal worsts, as one thread going through the units in order would.
  void merge(const RangeWorst& later) {
    checks += later.checks;
    if (later.excess_mm > excess_mm) excess_mm = later.excess_mm, where = later.where;
  }
};

// Each check compares the surface between some samples with their box widened by the slack. Where
// the curvature bound and the surface's distance from the samples themselves show that no place
// between them can leave that box by more than the worst excess found so far, the places are
// counted as checked and not evaluated: the figures are the same as evaluating every one (a
// surface within its samples' noise and curvature certifies nearly everywhere, which is what made
// the check of a million points cost seconds).
class NeighbourCheck {
 public:
  // `start_distances`: each sample's distance from the surface at its own parameters, when the
  // caller has them (orthogonal_distances' start distances); else they are evaluated here.
  NeighbourCheck(const BSplineSurface& surface, const PointCloud& cloud, const Parameters& params, double slack,
                 bool certify, const std::vector<double>* start_distances)
      : form_(surface), cloud_(cloud), params_(params), slack_(slack), certify_(certify), curvature_(surface),
        u_lo_(std::max(0.0, surface.u_min())), u_hi_(std::min(1.0, surface.u_max())), v_lo_(std::max(0.0, surface.v_min())),
        v_hi_(std::min(1.0, surface.v_max())) {
    if (!certify) return;
    if (start_distances && start_distances->size() == params.uv.size()) {
      off_ = start_distances->data();
    } else {
      own_off_ = parameter_distances(surface, cloud.points, params);
      off_ = own_off_.data();
    }
    span_.resize(params.uv.size());
    parallel_for(span_.size(), [&](size_t begin, size_t end, unsigned) {
      for (size_t i = begin; i < end; ++i) span_[i] = {curvature_.span_u(params.uv[i].u), curvature_.span_v(params.uv[i].v)};
    }, 4096);
  }

  // Samples the surface at `samples` parameters strictly between points a and b; `bulge` is how
  // far a smooth surface through them may rise above their box (from the curvature around them).
  void segment(size_t a, size_t b, int samples, double bulge, RangeWorst& out) const {
    const UV& p = params_.uv[a];
    const UV& q = params_.uv[b];
    if (certify_ && inside(p) && inside(q)) {
      // Off its chord by at most M h^2 / 8 (M along the segment, h its length).
      const double h_sq = (q.u - p.u) * (q.u - p.u) + (q.v - p.v) * (q.v - p.v);
      const double m = curvature_.over_spans(span_[a].first, span_[b].first, span_[a].second, span_[b].second);
      if (certified(std::max(off_[a], off_[b]) + m * h_sq / 8, bulge, out)) {
        out.checks += static_cast<size_t>(samples);
        return;
      }
    }
    const Point3* corners[2] = {&cloud_.points[a], &cloud_.points[b]};
    for (int k = 1; k <= samples; ++k) {
      const double t = static_cast<double>(k) / (samples + 1);
      check(lerp(p, q, t), corners, 2, bulge, out);
    }
  }
  // The centre of the cell of four neighbours.
  void cell(size_t a, size_t b, size_t c, size_t d, double bulge, RangeWorst& out) const {
    const UV* uv[4] = {&params_.uv[a], &params_.uv[b], &params_.uv[c], &params_.uv[d]};
    const UV centre{(uv[0]->u + uv[1]->u + uv[2]->u + uv[3]->u) / 4, (uv[0]->v + uv[1]->v + uv[2]->v + uv[3]->v) / 4};
    if (certify_ && inside(*uv[0]) && inside(*uv[1]) && inside(*uv[2]) && inside(*uv[3])) {
      // Within M/2 times the corners' mean squared distance from the centre of the corners' mean.
      const size_t index[4] = {a, b, c, d};
      int su0 = span_[a].first, su1 = su0, sv0 = span_[a].second, sv1 = sv0;
      double mean_sq = 0, off = 0;
      for (int k = 0; k < 4; ++k) {
        const std::pair<int, int>& span = span_[index[k]];
        su0 = std::min(su0, span.first), su1 = std::max(su1, span.first), sv0 = std::min(sv0, span.second), sv1 = std::max(sv1, span.second);
        mean_sq += ((uv[k]->u - centre.u) * (uv[k]->u - centre.u) + (uv[k]->v - centre.v) * (uv[k]->v - centre.v)) / 4;
        off = std::max(off, off_[index[k]]);
      }
      if (certified(off + curvature_.over_spans(su0, su1, sv0, sv1) * mean_sq / 2, bulge, out)) {
        ++out.checks;
        return;
      }
    }
    const Point3* corners[4] = {&cloud_.points[a], &cloud_.points[b], &cloud_.points[c], &cloud_.points[d]};
    check(centre, corners, 4, bulge, out);
  }

 private:
  static UV lerp(const UV& a, const UV& b, double t) { return {a.u + (b.u - a.u) * t, a.v + (b.v - a.v) * t}; }
  // Within the unit square and the surface's domain: there a sample's distance at its parameters
  // is the same whether they were clamped to the domain (closest_point's start) or not
  // (parameter_distances).
  bool inside(const UV& p) const { return p.u >= u_lo_ && p.u <= u_hi_ && p.v >= v_lo_ && p.v <= v_hi_; }
  // `reach`: how far the surface may be from the samples' box at the places between them, in
  // every coordinate. True when that cannot exceed the slack by the worst excess found so far
  // (strictly less, so an equal excess is still evaluated and the first of equals kept).
  bool certified(double reach, double bulge, const RangeWorst& out) const {
    const double bound = reach - (slack_ + bulge);
    return bound <= 0 || bound < std::max(out.excess_mm, out.floor_mm);
  }
  void check(const UV& uv, const Point3* const* corners, int count, double bulge, RangeWorst& out) const {
    const Point3 s = form_.evaluate(std::clamp(uv.u, 0.0, 1.0), std::clamp(uv.v, 0.0, 1.0));
    const double excess = box_excess(s, corners, count, slack_ + bulge);
    ++out.checks;
    if (excess > out.excess_mm) {
      out.excess_mm = excess;
      out.where = s;
    }
  }
  const PatchForm form_;  // the surface, for the places between the samples that are evaluated
  const PointCloud& cloud_;
  const Parameters& params_;
  double slack_;
  bool certify_;
  CurvatureBound curvature_;
  double u_lo_, u_hi_, v_lo_, v_hi_;
  const double* off_ = nullptr;  // each sample's distance from the surface at its own parameters
  std::vector<double> own_off_;  // those distances when evaluated here
  std::vector<std::pair<int, int>> span_;  // each sample's knot spans in u and v
};

// Runs unit(i, worst) for every `stride`-th i in [0, n) on every core, in fixed blocks of units
// with a RangeWorst each (starting from `floor_mm`), and merges the blocks in order: the figures
// do not depend on the number of threads.
template <typename Unit>
RangeWorst run_units(size_t n, size_t stride, double floor_mm, Unit& unit) {
  constexpr size_t kBlock = 64;
  const size_t units = (n + stride - 1) / stride;
  std::vector<RangeWorst> worst((units + kBlock - 1) / kBlock);
  for (RangeWorst& w : worst) w.floor_mm = floor_mm;
  parallel_for(worst.size(), [&](size_t begin, size_t end, unsigned) {
    for (size_t b = begin; b < end; ++b) {
      for (size_t i = b * kBlock; i < std::min(units, (b + 1) * kBlock); ++i) unit(i * stride, worst[b]);
    }
  }, 1);
  RangeWorst all;
  for (const RangeWorst& w : worst) all.merge(w);
  return all;
}

// Every unit's checks into `out`. A first look at every 16th unit finds a worst excess that lets
// the full pass certify most units below it.
template <typename Unit>
void check_units(size_t n, Unit unit, FitValidation& out) {
  const RangeWorst first_look = run_units(n, 16, 0.0, unit);
  RangeWorst all;
  all.excess_mm = out.range_excess_max_mm;
  all.where = out.range_worst;
  all.merge(run_units(n, 1, first_look.excess_mm, unit));
  out.neighbour_checks += all.checks;
  out.range_excess_max_mm = all.excess_mm;
  out.range_worst = all.where;
}

// Each point's four nearest neighbours in the parameter plane, itself among them.
// Read in place: a copy as Point3s was 24 MB for a million points, an eighth of the validation's
// peak, and fresh memory is dear (memory_reuse.h).
Neighbourhoods parameter_plane_neighbours(const Parameters& params) {
  return nearest_neighbours(params.uv.size(), [](const void* from, size_t i, double& u, double& v) {
    const UV& at = (*static_cast<const std::vector<UV>*>(from))[i];
    u = at.u, v = at.v;
  }, &params.uv, 5);
}

void check_neighbours(const BSplineSurface& surface, const PointCloud& cloud, const Parameters& params,
                      const ValidationOptions& options, const FoldSupport* support,
                      const std::vector<double>* start_distances, FitValidation& out) {
  // Scattered points: each point and its four nearest neighbours in the parameter plane, the
  // support's when it has found them. Found before the check's per-point arrays are made, so that
  // those take the memory the search's scratch leaves (8 MB less at the peak of a million points'
  // validation; fresh memory is dear, memory_reuse.h).
  std::optional<Neighbourhoods> own;
  const Neighbourhoods* found = nullptr;
  if (!cloud.line) {
    found = support ? support->plane_neighbours() : nullptr;
    if (!found) found = &own.emplace(parameter_plane_neighbours(params));
  }
  const NeighbourCheck check(surface, cloud, params, options.tolerance_mm, options.certify_by_curvature, start_distances);
  if (cloud.line) {
    const std::vector<std::vector<size_t>> lines = lines_of(cloud);
    // Each line's points by their parameter along the line, to pair a point with the nearest one
    // on a neighbouring line (asked only of lines that hold points).
    auto along = [&](size_t i) { return params.uv[i].u; };
    const SortedLines<decltype(along)> sorted(lines, along);
    auto nearest_on = [&](size_t l, size_t i) { return static_cast<size_t>(sorted.nearest_on(l, i)); };
    // The bulge a smooth surface may have over its samples' box: a parabola through three
    // neighbours rises |second difference| / 8 above its chord between two of them.
    std::vector<double> bulge_along(cloud.points.size(), 0.0), bulge_across(cloud.points.size(), 0.0);
    auto second = [&](size_t a, size_t b, size_t c) {
      const Point3 &p = cloud.points[a], &q = cloud.points[b], &r = cloud.points[c];
      const double dx = std::fabs(p.x - 2 * q.x + r.x), dy = std::fabs(p.y - 2 * q.y + r.y), dz = std::fabs(p.z - 2 * q.z + r.z);
      return std::max({dx, dy, dz}) / 8.0;
    };
    for (size_t l = 0; l < lines.size(); ++l) {
      const std::vector<size_t>& line = lines[l];
      for (size_t k = 1; k + 1 < line.size(); ++k) bulge_along[line[k]] = second(line[k - 1], line[k], line[k + 1]);
      if (line.size() >= 3) {
        bulge_along[line.front()] = bulge_along[line[1]];
        bulge_along[line.back()] = bulge_along[line[line.size() - 2]];
      }
      if (l == 0 || l + 1 == lines.size()) continue;
      for (size_t i : line) bulge_across[i] = second(nearest_on(l - 1, i), i, nearest_on(l + 1, i));
    }
    check_units(lines.size(), [&](size_t l, RangeWorst& worst) {
      const std::vector<size_t>& line = lines[l];
      for (size_t k = 1; k < line.size(); ++k) {
        const size_t a = line[k - 1], b = line[k];
        check.segment(a, b, options.samples_between, std::max(bulge_along[a], bulge_along[b]), worst);
      }
      if (l + 1 == lines.size() || line.empty() || lines[l + 1].empty()) return;
      for (size_t k = 0; k < line.size(); ++k) {
        const size_t a = line[k], c = nearest_on(l + 1, a);
        check.segment(a, c, options.samples_between, std::max(bulge_across[a], bulge_across[c]), worst);
        if (k > 0) {
          const size_t b = line[k - 1], d = nearest_on(l + 1, b);
          if (d == c) continue;
          double bulge = 0;
          for (size_t i : {a, b, c, d}) bulge = std::max(bulge, bulge_along[i] + bulge_across[i]);
          check.cell(b, a, c, d, bulge, worst);
        }
      }
    }, out);
    return;
  }
  const Neighbourhoods& near = *found;
  // Taken in the buckets' order, so each point's neighbours are mostly in the cache already.
  check_units(near.order.size(), [&](size_t position, RangeWorst& worst) {
    const size_t i = near.order[position];
    for (const uint32_t* j = near.at_position(position); j != near.at_position(position) + near.k; ++j) {
      if (*j > i) check.segment(i, *j, options.samples_between, 0.0, worst);
    }
  }, out);
}

}  // namespace

std::vector<int> validation_folds(const PointCloud& cloud, int folds) {
  std::vector<int> fold(cloud.points.size(), 0);
  if (folds < 2) return fold;
  if (cloud.line) {
    std::map<uint32_t, int> rank;
    for (uint32_t id : *cloud.line) rank.emplace(id, 0);
    int next = 0;
    for (auto& [id, r] : rank) r = next++;
    // The first and last lines are never held out: predicting them would test extrapolation past
    // the scan, not the surface between its samples.
    const int last = next - 1;
    for (size_t i = 0; i < fold.size(); ++i) {
      const int r = rank[(*cloud.line)[i]];
      fold[i] = (r == 0 || r == last) ? -1 : (r - 1) % folds;
    }
  } else {
    for (size_t i = 0; i < fold.size(); ++i) fold[i] = static_cast<int>(i % static_cast<size_t>(folds));
  }
  return fold;
}

FoldSupport::FoldSupport(const PointCloud& cloud, const Parameters& params, int folds, bool fill_outside,
                         bool neighbours)
    : fill_outside_(fill_outside), plane_params_(!cloud.line && neighbours ? &params : nullptr) {
  const std::vector<int> fold = validation_folds(cloud, folds);
  const size_t fold_count = static_cast<size_t>(std::max(folds, 0));
  // Each direction's parameters are sorted once, each with its fold: a fold's remaining points'
  // sorted parameters are that run without the fold's own, the same values in the same order as
  // sorting them alone, so one pass over it gives the sites distinct_sites() finds. (Sorting each
  // fold's group and merging the others took twice as long, one fold to a core.)
  struct Tagged {
    double value;
    int fold;
  };
  std::vector<Tagged> sorted[2];
  const double all_merge = site_merge_distance(fold.size());
  parallel_for(2, [&](size_t begin, size_t end, unsigned) {
    for (size_t direction = begin; direction < end; ++direction) {
      std::vector<Tagged>& run = sorted[direction];
      run.resize(fold.size());
      for (size_t i = 0; i < fold.size(); ++i) run[i] = {direction == 0 ? params.uv[i].u : params.uv[i].v, fold[i]};
      sort_by_buckets(run, all_merge, [](const Tagged& t) { return t.value; });
    }
  }, 1);
  std::vector<size_t> held(fold_count, 0);
  for (int f : fold) {
    if (f >= 0 && static_cast<size_t>(f) < fold_count) ++held[static_cast<size_t>(f)];
  }
  // Each fold's sites along each direction, then its index, as separate tasks on every core; the
  // last two tasks take every point, for all_sites_u/v.
  std::vector<std::vector<double>> sites(2 * fold_count + 2);
  parallel_for(sites.size(), [&](size_t begin, size_t end, unsigned) {
    for (size_t task = begin; task < end; ++task) {
      const int f = static_cast<int>(task / 2);
      const bool every_point = task >= 2 * fold_count;
      SiteGrouping grouping(every_point ? all_merge : site_merge_distance(fold.size() - held[task / 2]));
      for (const Tagged& t : sorted[task % 2]) {
        if (every_point || t.fold != f) grouping.add(t.value);
      }
      sites[task] = grouping.finish();
    }
  }, 1);
  all_sites_[0] = std::move(sites[2 * fold_count]);
  all_sites_[1] = std::move(sites[2 * fold_count + 1]);
  // The folds hold nearly equal numbers of points, so their buckets mostly have one side: every
  // point is bucketed once at the first fold's, and each fold takes its points out of that.
  const SiteIndex::Shared shared =
      fold_count == 0 ? SiteIndex::Shared{} : SiteIndex::share(params.uv, fold, fold.size() - held[0]);
  std::vector<std::optional<SiteIndex>> built(fold_count);
  parallel_for(built.size(), [&](size_t begin, size_t end, unsigned) {
    for (size_t f = begin; f < end; ++f) {
      built[f].emplace(params.uv, fold, static_cast<int>(f), std::move(sites[2 * f]), std::move(sites[2 * f + 1]), shared);
    }
  }, 1);
  kept_sites_.reserve(built.size());
  for (std::optional<SiteIndex>& index : built) kept_sites_.push_back(std::move(*index));
}

const Neighbourhoods* FoldSupport::plane_neighbours() const {
  if (!plane_neighbours_ && plane_params_) plane_neighbours_.emplace(parameter_plane_neighbours(*plane_params_));
  return plane_neighbours_ ? &*plane_neighbours_ : nullptr;
}

std::string FoldSupport::fold_problem(size_t f, const std::vector<double>& knots_u, int degree_u,
                                      const std::vector<double>& knots_v, int degree_v) const {
  const std::string which = "with validation fold " + std::to_string(f + 1) + " of " + std::to_string(kept_sites_.size());
  const SiteIndex& sites = kept_sites_[f];
  if (fill_outside_) {
    const std::vector<char> outside = outside_control_points(knots_u, degree_u, knots_v, degree_v, sites, kRegionMinProduct);
    const auto [i, j] = unmatched_control_point(knots_u, degree_u, knots_v, degree_v, sites, kRegionMinProduct, &outside);
    if (i < 0) return "";
    return which + " held out, the remaining points of the region cannot determine control point (" + std::to_string(i) +
           ", " + std::to_string(j) + ") of the net";
  }
  // A margin (each control point with a site where its basis function is at least 0.1) keeps
  // the nets the tolerance loop reaches well conditioned for every fold.
  if (schoenberg_whitney_gap(knots_u, degree_u, sites.sites_u(), 0.1) >= 0 ||
      schoenberg_whitney_gap(knots_v, degree_v, sites.sites_v(), 0.1) >= 0) {
    return which + " held out, the remaining points cannot determine the net";
  }
  const auto [i, j] = unmatched_control_point(knots_u, degree_u, knots_v, degree_v, sites, 0.01);
  if (i < 0) return "";
  return which + " held out, the remaining points cannot determine control point (" + std::to_string(i) + ", " +
         std::to_string(j) + ") of the net (a hole in the scan beside it)";
}

std::string FoldSupport::problem(const std::vector<double>& knots_u, int degree_u, const std::vector<double>& knots_v,
                                 int degree_v) const {
  // The folds are asked on every core (the tolerance loop asks this of every knot it would add: on
  // fit_bench's million points the sampled pass's last knots took about 60 ms of checks beside a
  // 13 ms fit), and the first fold with a problem answers, as asking them in turn would.
  std::vector<std::string> problems(kept_sites_.size());
  parallel_for(kept_sites_.size(), [&](size_t begin, size_t end, unsigned) {
    for (size_t f = begin; f < end; ++f) problems[f] = fold_problem(f, knots_u, degree_u, knots_v, degree_v);
  }, 1);
  for (std::string& problem : problems) {
    if (!problem.empty()) return problem;
  }
  return "";
}

FitValidation validate_fit(const PointCloud& cloud, const Parameters& params, const std::vector<double>* weights,
                           const BSplineSurface& surface, const ValidationOptions& options, const FoldSupport* support,
                           const std::vector<FoldRefit>* made, const std::vector<double>* start_distances) {
  FitValidation out;
  out.checked = true;
  out.folds = options.folds;
  out.folds_of_lines = cloud.line.has_value();
  if (support && support->folds() != options.folds) support = nullptr;
  const std::vector<int> fold = validation_folds(cloud, options.folds);
  LsqSpec spec;
  spec.degree_u = surface.degree_u;
  spec.degree_v = surface.degree_v;
  spec.knots_u = surface.knots_u;
  spec.knots_v = surface.knots_v;
  spec.fill_outside = options.fill_outside;
  // The refits use each fold's index of its remaining points: the caller's, or built here.
  std::vector<FoldRefit> own_refits;
  std::optional<FoldSupport> own_support;  // read by the checks between the samples too
  if (!made || made->size() != static_cast<size_t>(options.folds)) {
    if (!support && options.folds >= 1) support = &own_support.emplace(cloud, params, options.folds, options.fill_outside);
    std::vector<const SiteIndex*> kept_sites;
    for (int f = 0; f < options.folds; ++f) kept_sites.push_back(&support->kept_sites(f));
    own_refits = fit_least_squares_by_folds(cloud.points, params, weights, spec, fold, kept_sites);
    made = &own_refits;
  }
  const std::vector<FoldRefit>& refits = *made;
  double sum_sq = 0;
  for (int f = 0; f < options.folds; ++f) {
    std::vector<size_t> held;
    for (size_t i = 0; i < fold.size(); ++i) {
      if (fold[i] == f) held.push_back(i);
    }
    if (held.empty()) continue;
    const FoldRefit& refit = refits[static_cast<size_t>(f)];
    if (!refit.error.empty()) {
      out.problem = "cannot be validated: with fold " + std::to_string(f + 1) + " of " + std::to_string(options.folds) +
                    (cloud.line ? " (every " + std::to_string(options.folds) + "th scan line)" : "") +
                    " held out, " + refit.error;
      // The folds measured so far are no figure for the fit: none is reported.
      out.held_out_points = 0;
      out.held_out_max_mm = 0;
      return out;
    }
    std::vector<double> distance(held.size());
    with_fast_form(refit.surface, 2 * held.size(), [&](const auto& form) {
      parallel_for(held.size(), [&](size_t begin, size_t end, unsigned) {
        for (size_t n = begin; n < end; ++n) {
          const size_t i = held[n];
          distance[n] = std::fabs(closest_point(form, cloud.points[i], params.uv[i].u, params.uv[i].v).distance);
        }
      }, 1024);
    });
    for (size_t n = 0; n < held.size(); ++n) {
      const double d = distance[n];
      sum_sq += d * d;
      ++out.held_out_points;
      if (d > out.held_out_max_mm) {
        out.held_out_max_mm = d;
        out.held_out_worst = cloud.points[held[n]];
      }
    }
  }
  if (out.held_out_points > 0) out.held_out_rms_mm = std::sqrt(sum_sq / static_cast<double>(out.held_out_points));
  check_neighbours(surface, cloud, params, options, support, start_distances, out);
  if (!(options.tolerance_mm > 0)) return out;
  if (out.held_out_max_mm > options.tolerance_mm) {
    out.problem = "a surface fitted without the point " + at(out.held_out_worst) + " misses it by " +
                  mm(out.held_out_max_mm) + " (hold-out check, " + std::to_string(out.held_out_points) +
                  " points predicted, RMS " + mm(out.held_out_rms_mm) + ")";
  } else if (out.range_excess_max_mm > 0) {
    out.problem = "between neighbouring samples the surface leaves their range by " +
                  mm(out.range_excess_max_mm + options.tolerance_mm) + " at " + at(out.range_worst) +
                  " (it rings between the samples; a crease or step there?)";
  }
  out.passed = out.problem.empty();
  return out;
}

}  // namespace dg::host
