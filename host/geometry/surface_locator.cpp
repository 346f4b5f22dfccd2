// A bucket grid over surface samples and a ring search for the nearest one.
#include "host/geometry/surface_locator.h"

#include <algorithm>
#include <cmath>

#include "host/geometry/vec3.h"

namespace dg::host {

namespace {

std::vector<double> span_samples(const std::vector<double>& knots, double lo, double hi, int per_span) {
  const std::vector<double> distinct = distinct_knots(knots, lo, hi);
  const int spans = static_cast<int>(distinct.size()) - 1;
  per_span = std::max(1, std::min(per_span, 512 / std::max(1, spans)));
  std::vector<double> t;
  for (int s = 0; s < spans; ++s) {
    for (int k = 0; k < per_span; ++k) t.push_back(distinct[s] + (distinct[s + 1] - distinct[s]) * (k + 0.5) / per_span);
  }
  return t;
}

}  // namespace

SurfaceLocator::SurfaceLocator(const BSplineSurface& surface, int per_span) : surface_(surface), form_(surface) {
  const std::vector<double> us = span_samples(surface.knots_u, surface.u_min(), surface.u_max(), per_span);
  const std::vector<double> vs = span_samples(surface.knots_v, surface.v_min(), surface.v_max(), per_span);
  spacing_u_ = (surface.u_max() - surface.u_min()) / static_cast<double>(us.size());
  spacing_v_ = (surface.v_max() - surface.v_min()) / static_cast<double>(vs.size());
  Point3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  double spacing_sum = 0;
  for (double u : us) {
    for (double v : vs) {
      const Point3 p = form_.evaluate(u, v);
      samples_.push_back({p, u, v});
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
  }
  for (size_t k = 1; k < samples_.size(); ++k) spacing_sum += norm(samples_[k].point - samples_[k - 1].point);
  // Buckets about two sample spacings wide, at most 2^21 of them.
  cell_mm_ = std::max(1e-9, 2.0 * spacing_sum / static_cast<double>(std::max<size_t>(1, samples_.size() - 1)));
  auto count = [&](double extent) { return std::max(1, static_cast<int>(extent / cell_mm_) + 1); };
  while (static_cast<double>(count(hi.x - lo.x)) * count(hi.y - lo.y) * count(hi.z - lo.z) > 2097152.0) cell_mm_ *= 1.5;
  origin_ = lo;
  nx_ = count(hi.x - lo.x);
  ny_ = count(hi.y - lo.y);
  nz_ = count(hi.z - lo.z);
  const size_t buckets = static_cast<size_t>(nx_) * ny_ * nz_;
  first_.assign(buckets + 1, 0);
  std::vector<long> key(samples_.size());
  for (size_t k = 0; k < samples_.size(); ++k) {
    int x, y, z;
    cell_of(samples_[k].point, x, y, z);
    key[k] = cell_key(x, y, z);
    ++first_[static_cast<size_t>(key[k]) + 1];
  }
  for (size_t b = 1; b <= buckets; ++b) first_[b] += first_[b - 1];
  // The samples themselves in bucket order: a search reads each bucket's from one run of memory.
  std::vector<Sample> by_bucket(samples_.size());
  std::vector<size_t> next(first_.begin(), first_.end() - 1);
  for (size_t k = 0; k < samples_.size(); ++k) by_bucket[next[static_cast<size_t>(key[k])]++] = samples_[k];
  samples_.swap(by_bucket);
}

long SurfaceLocator::cell_key(int x, int y, int z) const { return (static_cast<long>(x) * ny_ + y) * nz_ + z; }

void SurfaceLocator::cell_of(const Point3& p, int& x, int& y, int& z) const {
  x = std::clamp(static_cast<int>(std::floor((p.x - origin_.x) / cell_mm_)), 0, nx_ - 1);
  y = std::clamp(static_cast<int>(std::floor((p.y - origin_.y) / cell_mm_)), 0, ny_ - 1);
  z = std::clamp(static_cast<int>(std::floor((p.z - origin_.z) / cell_mm_)), 0, nz_ - 1);
}

SurfaceLocator::Starts SurfaceLocator::starts(const Point3& p) const {
  int cx, cy, cz;
  cell_of(p, cx, cy, cz);
  // How far p lies inside its own bucket (a point outside the grid was clamped to an edge bucket).
  const double fx = (p.x - origin_.x) / cell_mm_ - cx, fy = (p.y - origin_.y) / cell_mm_ - cy, fz = (p.z - origin_.z) / cell_mm_ - cz;
  const bool inside = fx >= 0 && fx <= 1 && fy >= 0 && fy <= 1 && fz >= 0 && fz <= 1;
  const double inner_margin = cell_mm_ * std::min({fx, 1 - fx, fy, 1 - fy, fz, 1 - fz});
  // Rings of buckets around p's (clamped) bucket until no unvisited bucket can hold a nearer sample.
  // The samples of the first two rings are kept as candidates for a second start: the nearest one
  // more than two sample spacings from the nearest in parameters (the other side of a fold, or
  // another part of the surface near the same point).
  size_t best = 0;
  double best_d2 = HUGE_VAL;
  struct Candidate {
    size_t index;
    double d2;
  };
  Candidate near[256];
  size_t near_count = 0;
  const int max_ring = std::max({nx_, ny_, nz_});
  for (int ring = 0; ring <= max_ring; ++ring) {
    for (int x = std::max(0, cx - ring); x <= std::min(nx_ - 1, cx + ring); ++x) {
      for (int y = std::max(0, cy - ring); y <= std::min(ny_ - 1, cy + ring); ++y) {
        const bool x_or_y_on_ring = std::abs(x - cx) == ring || std::abs(y - cy) == ring;
        for (int z = std::max(0, cz - ring); z <= std::min(nz_ - 1, cz + ring); ++z) {
          // Only the shell of this ring: inner buckets were searched before.
          if (!x_or_y_on_ring && std::abs(z - cz) != ring) {
            if (cz + ring <= nz_ - 1 && z < cz + ring) z = cz + ring - 1;
            continue;
          }
          const long b = cell_key(x, y, z);
          for (size_t o = first_[static_cast<size_t>(b)]; o < first_[static_cast<size_t>(b) + 1]; ++o) {
            const Point3 d = samples_[o].point - p;
            const double d2 = dot(d, d);
            if (ring <= 1 && near_count < 256) near[near_count++] = {o, d2};
            if (d2 < best_d2) {
              best_d2 = d2;
              best = o;
            }
          }
        }
      }
    }
    // Every bucket beyond this ring is at least ring * cell away from p's bucket, and beyond p's own
    // bucket at least p's distance to that bucket's nearest face (p inside it). The second start is
    // sought within 1.5 times the best distance: once both lie inside what was searched, no
    // further bucket can change either.
    double reach = ring * cell_mm_;
    if (ring == 0 && inside) reach = inner_margin;
    if (best_d2 < HUGE_VAL && reach * reach >= (ring == 0 ? 2.25 * best_d2 : best_d2)) break;
  }
  const Sample& first = samples_[best];
  size_t other = samples_.size();
  double other_d2 = 2.25 * best_d2;
  for (size_t k = 0; k < near_count; ++k) {
    const Sample& s = samples_[near[k].index];
    if (near[k].d2 > other_d2) continue;
    if (std::fabs(s.u - first.u) <= 2 * spacing_u_ && std::fabs(s.v - first.v) <= 2 * spacing_v_) continue;
    other_d2 = near[k].d2;
    other = near[k].index;
  }
  return {best, other};
}

Closest SurfaceLocator::closest(const Point3& p) const {
  const Starts s = starts(p);
  Closest result = closest_point(form_, p, samples_[s.nearest].u, samples_[s.nearest].v);
  if (s.second < samples_.size()) {
    const Closest second = closest_point(form_, p, samples_[s.second].u, samples_[s.second].v);
    if (std::fabs(second.distance) < std::fabs(result.distance)) result = second;
  }
  return result;
}

}  // namespace dg::host
