// The points' parameters bucketed over the unit square, and their distinct sites along u and v.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "host/fit/parameterize.h"

namespace dg::host {

// Built once per point set and shared by every support check of a refinement loop: a check then
// visits only the points under one control point's support instead of all of them, and the sorted
// sites are not sorted again for every candidate knot. Holds a pointer to `uv`, which must outlive it.
class SiteIndex {
 public:
  // `buckets` false: the sites only, for a check that never visits (visit() then finds nothing).
  explicit SiteIndex(const std::vector<UV>& uv, bool buckets = true);
  explicit SiteIndex(std::vector<UV>&&, bool = true) = delete;  // it would point at a temporary
  // The same with the sites already found (distinct_sites() of uv with site_merge_distance() of
  // its size: FoldSupport::all_sites_u/v find them in the pass that sorts for its folds).
  SiteIndex(const std::vector<UV>& uv, std::vector<double> sites_u, std::vector<double> sites_v, bool buckets);
  // Only the points k with group[k] != left_out (a validation fold's remaining points), whose
  // distinct sites (distinct_sites() of their uv, site_merge_distance() of their count) the caller
  // found, having sorted once for several such indexes (FoldSupport). visit() gives their numbers
  // in uv, the whole set's.
  SiteIndex(const std::vector<UV>& uv, const std::vector<int>& group, int left_out, std::vector<double> sites_u,
            std::vector<double> sites_v);
  // Every point bucketed once, with its group, for several such indexes of one point set: an index
  // whose buckets have the same side takes its points out of these in one pass instead of
  // bucketing them again (FoldSupport's five folds spent 0.07 s doing that for a million points).
  struct Shared {
    size_t side = 0;
    std::vector<uint32_t> start;  // as start_ and order_ over every point
    std::vector<uint32_t> order;
    std::vector<int> group_in_order;  // group[order[n]]
  };
  static Shared share(const std::vector<UV>& uv, const std::vector<int>& group, size_t subset_count);
  SiteIndex(const std::vector<UV>& uv, const std::vector<int>& group, int left_out, std::vector<double> sites_u,
            std::vector<double> sites_v, const Shared& shared);
  // Whether the index holds only some of uv's points.
  bool subset() const { return subset_; }

  const std::vector<UV>& uv() const { return *uv_; }
  // distinct_sites() along u and v with site_merge_distance() of this many points.
  const std::vector<double>& sites_u() const { return sites_u_; }
  const std::vector<double>& sites_v() const { return sites_v_; }

  // Calls visit(k) for every point k with u in [u_lo, u_hi] and v in [v_lo, v_hi] (and some just
  // outside, in the same buckets) until visit returns false.
  // Buckets are visited from the rectangle's centre outwards, so a search that stops early finds
  // the points where a control point's basis function is largest first, not its support's fringe.
  template <typename Visit>
  void visit(double u_lo, double u_hi, double v_lo, double v_hi, Visit visit) const {
    const size_t bu0 = bucket(u_lo), bu1 = bucket(u_hi), bv0 = bucket(v_lo), bv1 = bucket(v_hi);
    if (start_.empty() || bu1 < bu0 || bv1 < bv0) return;
    const size_t rows = bv1 - bv0 + 1, columns = bu1 - bu0 + 1;
    for (size_t r = 0; r < rows; ++r) {
      const size_t bv = centre_out(bv0, rows, r);
      for (size_t c = 0; c < columns; ++c) {
        const size_t b = bv * side_ + centre_out(bu0, columns, c);
        for (uint32_t n = start_[b]; n < start_[b + 1]; ++n) {
          if (!visit(static_cast<size_t>(order_[n]))) return;
        }
      }
    }
  }

 private:
  // The n-th of `count` buckets from `first` in the order middle, middle + 1, middle - 1, ...
  static size_t centre_out(size_t first, size_t count, size_t n) {
    const size_t middle = (count - 1) / 2, step = (n + 1) / 2;
    return first + (n % 2 == 1 ? middle + step : middle - step);
  }
  size_t bucket(double t) const { return bucket_at(t, side_); }
  static size_t bucket_at(double t, size_t side);
  static size_t side_for(size_t count);
  // Over the points k with (*group)[k] != left_out, or every point without `group`.
  void build_buckets(const std::vector<int>* group, int left_out);
  // The counting sort of the points `included(k)` into side x side buckets: bucket b's points are
  // order[start[b] .. start[b + 1]), in point order; placed(n, k) is told that point k went to
  // order[n].
  template <typename Included, typename Placed>
  static void sort_into_buckets(const std::vector<UV>& uv, size_t side, Included included, std::vector<uint32_t>& start,
                                std::vector<uint32_t>& order, Placed placed) {
    start.assign(side * side + 1, 0);
    std::vector<uint32_t> bucket_of(uv.size());
    size_t count = 0;
    for (size_t k = 0; k < uv.size(); ++k) {
      if (!included(k)) continue;
      bucket_of[k] = static_cast<uint32_t>(bucket_at(uv[k].v, side) * side + bucket_at(uv[k].u, side));
      ++start[bucket_of[k] + 1];
      ++count;
    }
    for (size_t b = 0; b + 1 < start.size(); ++b) start[b + 1] += start[b];
    order.resize(count);
    std::vector<uint32_t> next(start.begin(), start.end() - 1);
    for (size_t k = 0; k < uv.size(); ++k) {
      if (!included(k)) continue;
      const uint32_t n = next[bucket_of[k]]++;
      order[n] = static_cast<uint32_t>(k);
      placed(n, k);
    }
  }

  const std::vector<UV>* uv_;
  bool subset_ = false;
  size_t side_ = 1;               // buckets per direction
  std::vector<uint32_t> start_;   // bucket b's points are order_[start_[b] .. start_[b + 1])
  std::vector<uint32_t> order_;
  std::vector<double> sites_u_, sites_v_;
};

}  // namespace dg::host
