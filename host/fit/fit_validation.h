// Checking a fitted surface between its samples, where the fit itself never looked.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "host/fit/bspline_fit.h"
#include "host/geometry/fitted_surface.h"
#include "host/scan/neighbours.h"
#include "host/scan/point_reader.h"

namespace dg::host {

// Which validation fold each point belongs to: whole scan lines (every `folds`-th line by line
// order; the first and last lines belong to none, -1, and are never held out), or for points
// without lines every `folds`-th point. A point of fold f is held out when fold f is checked.
std::vector<int> validation_folds(const PointCloud& cloud, int folds);

// Whether every fold's remaining points can still determine the net (Schoenberg-Whitney along both
// directions); the reason when not. The tolerance loop asks this before it adds a knot, so the net
// it reaches can always be validated.
class FoldSupport {
 public:
  // `fill_outside`: a region's net (LsqSpec::fill_outside), whose control points beyond the points
  // are placed, not fitted; only the others must be determined. The indexes refer to params.uv,
  // which must outlive the FoldSupport.
  // `neighbours`: false for a caller that will not validate (the tolerance loop's sampled first
  // pass, which only finds knots), sparing the search below.
  FoldSupport(const PointCloud& cloud, const Parameters& params, int folds, bool fill_outside = false,
              bool neighbours = true);
  FoldSupport(const FoldSupport&) = delete;  // one index per fold, built once
  FoldSupport& operator=(const FoldSupport&) = delete;
  std::string problem(const std::vector<double>& knots_u, int degree_u, const std::vector<double>& knots_v,
                      int degree_v) const;

  int folds() const { return static_cast<int>(kept_sites_.size()); }
  // Every point's distinct sites along u and v (distinct_sites() with site_merge_distance() of the
  // whole set), found in the same pass as the folds': the tolerance loop's SiteIndex takes them
  // instead of sorting a million parameters again.
  const std::vector<double>& all_sites_u() const { return all_sites_[0]; }
  const std::vector<double>& all_sites_v() const { return all_sites_[1]; }
  // Fold f's remaining points, indexed over the whole set's parameters (SiteIndex::subset), for
  // validate_fit's refits.
  const SiteIndex& kept_sites(int f) const { return kept_sites_[static_cast<size_t>(f)]; }
  // For a cloud without scan lines, each point's four nearest neighbours in the parameter plane
  // (and itself), for the checks between neighbouring samples; null for one with lines, or for a
  // support made without `neighbours`. Found on every core when first asked, and kept for the
  // validations of other nets on the same points. (A search started as the support was made, on
  // a thread of its own beside the fit, slowed the fit's passes on both cores: the steps of
  // `fit --ctrl` on a million points, timed on their own, took 0.78-0.84 s with it and 0.73-0.77 s
  // without; the whole command's CPU time went from 1.32 to 1.22 s at the same wall time.) Not for
  // two threads at once.
  const Neighbourhoods* plane_neighbours() const;

 private:
  // Fold f's problem, or "" (problem() asks every fold).
  std::string fold_problem(size_t f, const std::vector<double>& knots_u, int degree_u, const std::vector<double>& knots_v,
                           int degree_v) const;
  std::vector<SiteIndex> kept_sites_;  // per fold, the points that remain
  std::vector<double> all_sites_[2];
  bool fill_outside_ = false;
  const Parameters* plane_params_ = nullptr;  // the parameters whose neighbours are wanted, if any
  mutable std::optional<Neighbourhoods> plane_neighbours_;
};

struct ValidationOptions {
  double tolerance_mm = 0;  // 0: measure only, decide nothing
  int folds = 5;
  // Parameters evaluated between each pair of neighbours (besides the quad centres).
  int samples_between = 3;
  bool fill_outside = false;  // the refits place control points beyond the points (LsqSpec::fill_outside)
  // Places between samples that the surface's curvature bound (host/geometry/curvature_bound.h)
  // and its distance from the samples show to be no worse than the worst found are counted, not
  // evaluated; false evaluates every one (the same figures, for tests to compare).
  bool certify_by_curvature = true;
};

// Two checks of a least-squares B-spline fit between the samples:
//  1. hold-out: for each fold the net (same knots) is fitted again without the fold's points and the
//     held-out points' orthogonal distances to that surface are measured: the surface's error where
//     it saw no data, plus the noise;
//  2. neighbours: between neighbouring samples (along a line, across to the next line, and at the
//     centre of the cell four of them make) the surface must stay within their bounding box widened
//     by the tolerance; a surface that rings between the samples leaves it.
// With a tolerance, `passed` says both held; `problem` says where the worst failure is, or why the
// fit could not be validated (a fold whose remaining points cannot determine the net).
// `support`, when given, is the FoldSupport of the same cloud, parameters and folds: its indexes
// spare every refit a pass over the points. `refits`, when given, are the folds' refits already
// made (fit_least_squares_with_folds, with validation_folds and `support`'s indexes).
// `start_distances`, when given, are each point's distance from `surface` at its own parameters
// (orthogonal_distances' start distances, which the caller measured anyway): the checks between
// the samples take them instead of evaluating the surface at every point again.
FitValidation validate_fit(const PointCloud& cloud, const Parameters& params, const std::vector<double>* weights,
                           const BSplineSurface& surface, const ValidationOptions& options,
                           const FoldSupport* support = nullptr, const std::vector<FoldRefit>* refits = nullptr,
                           const std::vector<double>* start_distances = nullptr);

}  // namespace dg::host
