// A counting sort of the points into square buckets, about four points to a bucket.
#include "host/fit/site_index.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "host/fit/knot_support.h"
#include "host/parallel/parallel_for.h"

namespace dg::host {

SiteIndex::SiteIndex(const std::vector<UV>& uv, bool buckets) : uv_(&uv) {
  if (uv.size() >= UINT32_MAX) throw std::length_error("more than 4 billion points");
  // The two directions' sorts are the bulk of the work: one on each of two cores.
  const double merge = site_merge_distance(uv.size());
  parallel_for(2, [&](size_t begin, size_t end, unsigned) {
    for (size_t direction = begin; direction < end; ++direction) {
      (direction == 0 ? sites_u_ : sites_v_) = distinct_sites(uv, direction == 0, merge);
    }
  }, 1);
  if (buckets) build_buckets(nullptr, 0);
}

SiteIndex::SiteIndex(const std::vector<UV>& uv, std::vector<double> sites_u, std::vector<double> sites_v, bool buckets)
    : uv_(&uv), sites_u_(std::move(sites_u)), sites_v_(std::move(sites_v)) {
  if (uv.size() >= UINT32_MAX) throw std::length_error("more than 4 billion points");
  if (buckets) build_buckets(nullptr, 0);
}

SiteIndex::SiteIndex(const std::vector<UV>& uv, const std::vector<int>& group, int left_out,
                     std::vector<double> sites_u, std::vector<double> sites_v)
    : uv_(&uv), subset_(true), sites_u_(std::move(sites_u)), sites_v_(std::move(sites_v)) {
  if (uv.size() >= UINT32_MAX) throw std::length_error("more than 4 billion points");
  build_buckets(&group, left_out);
}

SiteIndex::SiteIndex(const std::vector<UV>& uv, const std::vector<int>& group, int left_out,
                     std::vector<double> sites_u, std::vector<double> sites_v, const Shared& shared)
    : uv_(&uv), subset_(true), sites_u_(std::move(sites_u)), sites_v_(std::move(sites_v)) {
  if (uv.size() >= UINT32_MAX) throw std::length_error("more than 4 billion points");
  size_t count = 0;
  for (int g : group) count += g != left_out;
  if (shared.side != side_for(count) || shared.order.size() != uv.size()) {
    build_buckets(&group, left_out);
    return;
  }
  // The shared buckets without the left-out group: each bucket's points stay in point order, as
  // build_buckets() places them.
  side_ = shared.side;
  start_.assign(side_ * side_ + 1, 0);
  order_.resize(count);
  uint32_t kept = 0;
  for (size_t b = 0; b + 1 < shared.start.size(); ++b) {
    start_[b] = kept;
    for (uint32_t n = shared.start[b]; n < shared.start[b + 1]; ++n) {
      if (shared.group_in_order[n] != left_out) order_[kept++] = shared.order[n];
    }
  }
  start_.back() = kept;
}

SiteIndex::Shared SiteIndex::share(const std::vector<UV>& uv, const std::vector<int>& group, size_t subset_count) {
  Shared shared;
  if (uv.size() >= UINT32_MAX || group.size() != uv.size()) return shared;
  shared.side = side_for(subset_count);
  shared.group_in_order.resize(uv.size());
  sort_into_buckets(uv, shared.side, [](size_t) { return true; }, shared.start, shared.order,
                    [&](uint32_t n, size_t k) { shared.group_in_order[n] = group[k]; });
  return shared;
}

size_t SiteIndex::side_for(size_t count) {
  return static_cast<size_t>(std::clamp(std::sqrt(static_cast<double>(count) / 4.0), 1.0, 2048.0));
}

void SiteIndex::build_buckets(const std::vector<int>* group, int left_out) {
  const std::vector<UV>& uv = *uv_;
  auto included = [&](size_t k) { return !group || (*group)[k] != left_out; };
  size_t count = 0;
  for (size_t k = 0; k < uv.size(); ++k) count += included(k);
  side_ = side_for(count);
  sort_into_buckets(uv, side_, included, start_, order_, [](uint32_t, size_t) {});
}

size_t SiteIndex::bucket_at(double t, size_t side) {
  // Parameters lie on [0, 1]; anything else (or NaN) goes to the nearest edge bucket.
  if (!(t > 0)) return 0;
  if (!(t < 1)) return side - 1;
  return std::min(side - 1, static_cast<size_t>(t * static_cast<double>(side)));
}

}  // namespace dg::host
