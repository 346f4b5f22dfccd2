// A counting sort of the points into square buckets, about four points to a bucket.
#include "host/fit/site_index.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

SiteIndex::SiteIndex(const std::vector<UV>& uv, const std::vector<int>& group, int left_out,
                     std::vector<double> sites_u, std::vector<double> sites_v)
    : uv_(&uv), subset_(true), sites_u_(std::move(sites_u)), sites_v_(std::move(sites_v)) {
  if (uv.size() >= UINT32_MAX) throw std::length_error("more than 4 billion points");
  build_buckets(&group, left_out);
}

void SiteIndex::build_buckets(const std::vector<int>* group, int left_out) {
  const std::vector<UV>& uv = *uv_;
  auto included = [&](size_t k) { return !group || (*group)[k] != left_out; };
  size_t count = 0;
  for (size_t k = 0; k < uv.size(); ++k) count += included(k);
  side_ = static_cast<size_t>(std::clamp(std::sqrt(static_cast<double>(count) / 4.0), 1.0, 2048.0));
  start_.assign(side_ * side_ + 1, 0);
  std::vector<uint32_t> bucket_of(uv.size());
  for (size_t k = 0; k < uv.size(); ++k) {
    if (!included(k)) continue;
    bucket_of[k] = static_cast<uint32_t>(bucket(uv[k].v) * side_ + bucket(uv[k].u));
    ++start_[bucket_of[k] + 1];
  }
  for (size_t b = 0; b + 1 < start_.size(); ++b) start_[b + 1] += start_[b];
  order_.resize(count);
  std::vector<uint32_t> next(start_.begin(), start_.end() - 1);
  for (size_t k = 0; k < uv.size(); ++k) {
    if (included(k)) order_[next[bucket_of[k]]++] = static_cast<uint32_t>(k);
  }
}

size_t SiteIndex::bucket(double t) const {
  // Parameters lie on [0, 1]; anything else (or NaN) goes to the nearest edge bucket.
  if (!(t > 0)) return 0;
  if (!(t < 1)) return side_ - 1;
  return std::min(side_ - 1, static_cast<size_t>(t * static_cast<double>(side_)));
}

}  // namespace dg::host
