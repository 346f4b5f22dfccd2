// Whether data can determine a net: the Schoenberg-Whitney condition along each parameter direction.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "host/fit/parameterize.h"
#include "host/fit/site_index.h"

namespace dg::host {

// The distinct parameter values ("sites") of the points along one direction: values closer than
// `merge` to the first value of their group count once, so the points of one scan line (whose v
// differ only by the table's jitter) are one site, not hundreds. Sorted, each the group's mean.
std::vector<double> distinct_sites(const std::vector<UV>& uv, bool along_u, double merge);

// distinct_sites() of values already sorted ascending.
std::vector<double> sites_of_sorted(const std::vector<double>& sorted, double merge);

// The same one value at a time, ascending: for a caller that picks the values out of a larger
// sorted run (a validation fold's remaining points out of all of them).
class SiteGrouping {
 public:
  explicit SiteGrouping(double merge) : merge_(merge) {}
  void add(double value) {
    if (count_ > 0 && value - first_ > merge_) close_site();
    if (count_ == 0) first_ = value;
    sum_ += value;  // in ascending order, the sum distinct_sites() always took
    ++count_;
  }
  std::vector<double> finish() {
    if (count_ > 0) close_site();
    return std::move(sites_);
  }

 private:
  void close_site() {
    sites_.push_back(sum_ / static_cast<double>(count_));
    sum_ = 0;
    count_ = 0;
  }
  double merge_;
  double first_ = 0, sum_ = 0;
  size_t count_ = 0;
  std::vector<double> sites_;
};

// The merge distance for distinct_sites(): a tenth of the spacing of an even grid of that many points.
double site_merge_distance(size_t points);

// A step's ramp: a span between two knots of multiplicity `degree` (C0 at both) with no site inside.
// Nothing measures the surface there, so its degree - 1 inner control points are not fitted but
// placed on the straight line between the span's end control points (at their Greville abscissae):
// the surface crosses the gap as a straight ramp. The fit eliminates them (bspline_fit.cpp) and the
// support check does not ask sites of them.
struct RampPoint {
  int index = 0;          // the control point placed on the line
  int left = 0, right = 0;  // the span's end control points (interpolating at its ends)
  double weight_right = 0;  // index = (1 - w) left + w right
};
std::vector<RampPoint> ramp_points(const std::vector<double>& knots, int degree, const std::vector<double>& sites);

// The Schoenberg-Whitney condition for a clamped knot vector: basis functions 0..count-1 can each be
// given a site of their own, in increasing order, with N_i(site) != 0. It holds exactly when the
// collocation matrix of the sites has full rank, so a direction that fails it has more control
// points than its data can determine. Returns -1 when it holds, else the first basis function left
// without a site.
// Ramp points (above) are skipped. With `min_basis` > 0 a site counts for N_i only where
// N_i(site) >= min_basis: a margin that keeps the collocation matrix well conditioned, not just
// non-singular (a site at the tail of a support determines its control point only weakly).
int schoenberg_whitney_gap(const std::vector<double>& knots, int degree, const std::vector<double>& sites,
                           double min_basis = 0.0);

// The condition for the whole tensor-product net: every control point (ramp points aside) can be
// given a point of its own with N_i(u) N_j(v) > min_product (a bipartite matching). Each direction
// may pass on its own while a hole in the scan (outliers left out, or a validation fold held out
// beside one) leaves two control points near it sharing the few points under both. Returns
// {-1, -1} when it holds, else a control point (i along u, j along v) left without a point.
// Control points flagged in `outside` (index i * count_v + j) are not asked for a point.
std::pair<int, int> unmatched_control_point(const std::vector<double>& knots_u, int degree_u,
                                            const std::vector<double>& knots_v, int degree_v, const SiteIndex& index,
                                            double min_product = 0.0, const std::vector<char>* outside = nullptr);

// For a net fitted to one region of a scan (host/fit/regions.h): the control points whose support
// holds no point at all, flagged by index i * count_v + j. They lie beyond the region, where its
// trimmed surface is not used; the fit places them (bspline_fit.h's fill_outside) instead of
// refusing the net.
// With `min_product` > 0 a control point whose basis reaches at most that at every point counts as
// outside too: a sliver of support determines it too weakly to fit.
std::vector<char> outside_control_points(const std::vector<double>& knots_u, int degree_u,
                                         const std::vector<double>& knots_v, int degree_v, const SiteIndex& index,
                                         double min_product = 0.0);

// The margin region fits use: a control point is fitted only where its basis reaches 1 % somewhere.
constexpr double kRegionMinProduct = 0.01;

// The same check for both directions of a net, with the reason in words ("" when it holds): how
// many sites there are, how many control points were asked, and where the support is empty.
// With `outside`, only the tensor matching for the other control points is checked (a region's
// points need not cover every row and column of the net's box).
std::string net_support_problem(const std::vector<double>& knots_u, int degree_u, const std::vector<double>& knots_v,
                                int degree_v, const SiteIndex& index, const Parameters& params,
                                const std::vector<char>* outside = nullptr);

}  // namespace dg::host
