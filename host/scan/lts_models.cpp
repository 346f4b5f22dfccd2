// The LTS filter's local models: a trimmed polynomial over a window, a quadratic along a line.
#include "host/scan/lts_models.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "host/scan/median.h"

namespace dg::host::lts {

namespace {

// z = a + b t + c t^2 through points at distances t from point i, by its normal equations.
struct LineQuadratic {
  bool ok = false;
  double m[3][3] = {}, rhs[3] = {};
  double coefficient[3] = {};
  double det = 0;
  double scale = 0;  // residual scale over n - 3 degrees of freedom
  double gain = 0;   // [(X^T X)^-1]_00: the variance of the value at t = 0 over the noise's
};

LineQuadratic line_quadratic(const std::vector<double>& ts, const std::vector<double>& zs) {
  LineQuadratic q;
  const size_t n = ts.size();
  for (size_t k = 0; k < n; ++k) {
    const double row[3] = {1, ts[k], ts[k] * ts[k]};
    for (int a = 0; a < 3; ++a) {
      q.rhs[a] += row[a] * zs[k];
      for (int b = 0; b < 3; ++b) q.m[a][b] += row[a] * row[b];
    }
  }
  // Solved by Cramer's rule: the distinct t of at least four points keep them well conditioned.
  auto det3 = [](const double (&x)[3][3]) {
    return x[0][0] * (x[1][1] * x[2][2] - x[1][2] * x[2][1]) - x[0][1] * (x[1][0] * x[2][2] - x[1][2] * x[2][0]) +
           x[0][2] * (x[1][0] * x[2][1] - x[1][1] * x[2][0]);
  };
  q.det = det3(q.m);
  if (n < 4 || !(std::fabs(q.det) > 1e-12)) return q;
  for (int col = 0; col < 3; ++col) {
    double x[3][3];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) x[a][b] = b == col ? q.rhs[a] : q.m[a][b];
    q.coefficient[col] = det3(x) / q.det;
  }
  double ss = 0;
  for (size_t k = 0; k < n; ++k) {
    const double r = zs[k] - (q.coefficient[0] + q.coefficient[1] * ts[k] + q.coefficient[2] * ts[k] * ts[k]);
    ss += r * r;
  }
  q.scale = std::sqrt(ss / static_cast<double>(n - 3));
  // The cofactor over the determinant.
  q.gain = (q.m[1][1] * q.m[2][2] - q.m[1][2] * q.m[2][1]) / q.det;
  q.ok = true;
  return q;
}

}  // namespace

LooFit line_model(const std::vector<Point3>& points, const LineSide& reach, size_t i, const std::vector<char>& suspect,
                  double sigma) {
  LooFit out;
  std::vector<double> ts, zs;
  for (size_t j : reach) {
    if (suspect[j] || ts.size() >= static_cast<size_t>(kLinePoints)) continue;
    ts.push_back(std::hypot(points[j].x - points[i].x, points[j].y - points[i].y));
    zs.push_back(points[j].z);
  }
  const LineQuadratic q = line_quadratic(ts, zs);
  if (!q.ok) return out;
  const int n = static_cast<int>(ts.size());
  out.prediction = q.coefficient[0];
  out.scale = q.scale;
  out.near_kept = 4;
  // Skipped suspects push the points away and the gain up; beyond kLineGainMax the prediction is
  // too loose to vouch for anything.
  out.gain = q.gain;
  out.curved = true;
  // [(X^T X)^-1]_22 for the quadratic term's standard error.
  const auto& m = q.m;
  const double curvature_se = sigma * std::sqrt((m[0][0] * m[1][1] - m[0][1] * m[1][0]) / q.det);
  if (std::fabs(q.coefficient[2]) <= 2 * curvature_se) {
    // z = a + b t: [(X^T X)^-1]_00 = sum t^2 / (n sum t^2 - (sum t)^2).
    const double line_det = m[0][0] * m[1][1] - m[0][1] * m[0][1];
    const double a = (m[1][1] * q.rhs[0] - m[0][1] * q.rhs[1]) / line_det, b = (m[0][0] * q.rhs[1] - m[0][1] * q.rhs[0]) / line_det;
    double line_ss = 0;
    for (int k = 0; k < n; ++k) {
      const double r = zs[static_cast<size_t>(k)] - (a + b * ts[static_cast<size_t>(k)]);
      line_ss += r * r;
    }
    out.prediction = a;
    out.scale = std::sqrt(line_ss / (n - 2));
    out.gain = m[1][1] / line_det;
    out.curved = false;
  }
  out.ok = out.gain <= kLineGainMax;
  return out;
}

LooFit through_line_model(const std::vector<Point3>& points, const LineSide& before, const LineSide& after, size_t i,
                          const std::vector<char>& suspect) {
  LooFit out;
  std::vector<double> ts, zs;
  for (int side = 0; side < 2; ++side) {
    size_t taken = 0;
    for (size_t j : side == 0 ? before : after) {
      if (suspect[j] || taken == static_cast<size_t>(kThroughLineSide)) continue;
      ts.push_back((side == 0 ? -1 : 1) * std::hypot(points[j].x - points[i].x, points[j].y - points[i].y));
      zs.push_back(points[j].z);
      ++taken;
    }
    if (taken < 2) return out;
  }
  const LineQuadratic q = line_quadratic(ts, zs);
  if (!q.ok) return out;
  out.ok = true;
  out.prediction = q.coefficient[0];
  out.scale = q.scale;
  out.gain = q.gain;
  out.dof = static_cast<int>(ts.size()) - 3;
  out.near_kept = 2;
  return out;
}

std::vector<size_t> others_in(IndexSpan window, size_t i, const std::vector<char>& excluded) {
  std::vector<size_t> out;
  for (size_t j : window) {
    if (j != i && !excluded[j]) out.push_back(j);
  }
  return out;
}

size_t nearest_four(const std::vector<Point3>& points, const std::vector<size_t>& members, size_t i, size_t (&out)[4],
                    std::vector<std::pair<double, size_t>>& scratch) {
  scratch.clear();
  // Filled by index, not pushed: a pair pushed from the stack is reloaded as one 16-byte word that
  // the two 8-byte stores before it cannot forward (see set_ranked).
  scratch.resize(members.size());
  for (size_t m = 0; m < members.size(); ++m) {
    const size_t j = members[m];
    scratch[m].first = std::hypot(points[j].x - points[i].x, points[j].y - points[i].y);
    scratch[m].second = j;
  }
  const size_t count = std::min<size_t>(4, scratch.size());
  std::partial_sort(scratch.begin(), scratch.begin() + static_cast<std::ptrdiff_t>(count), scratch.end());
  for (size_t m = 0; m < count; ++m) out[m] = scratch[m].second;
  return count;
}

std::vector<size_t> nearest_four(const std::vector<Point3>& points, const std::vector<size_t>& members, size_t i) {
  size_t nearest[4];
  std::vector<std::pair<double, size_t>> scratch;
  const size_t count = nearest_four(points, members, i, nearest, scratch);
  return std::vector<size_t>(nearest, nearest + count);
}

namespace {

// One thread's buffers for loo_model, which runs for every point and several of its windows: held
// across calls, its dozen small vectors cost no allocation (they were a tenth of its instructions).
struct LooScratch {
  std::vector<double> xs, ys, heights;
  std::vector<Ranked> by_residual;
  std::vector<size_t> chosen, start, fitted_set, kept_set, subset, kept_first, kept_second;
  std::vector<std::pair<double, size_t>> ranked_points;
};

}  // namespace

LooModel loo_model(const std::vector<Point3>& points, const std::vector<size_t>& window, size_t i,
                   const std::vector<double>& reference, int max_order, double keep,
                   WindowMisses* misses, bool tilt_on_slopes) {
  thread_local LooScratch scratch;
  LooModel out;
  const int n = static_cast<int>(window.size());
  if (n < 3) return out;
  // A model needs as many distinct x and y positions as its order plus one; a window on one line
  // (the half-plane beyond a point on the scan's edge) determines no surface and is no evidence.
  std::vector<double>& xs = scratch.xs;
  std::vector<double>& ys = scratch.ys;
  // By index: pushing onto these thread-local vectors stored each one's end in thread-local memory
  // at every point.
  xs.resize(window.size());
  ys.resize(window.size());
  for (size_t m = 0; m < window.size(); ++m) xs[m] = points[window[m]].x, ys[m] = points[window[m]].y;
  // Distinct positions as sorting and merging each value within 1e-6 of the last one kept would
  // count them, up to four (all the order needs): each next group starts at the least value that
  // its predecessor's first does not take in, found by a pass instead of a sort.
  auto distinct = [](const std::vector<double>& v) {
    if (v.empty()) return 0;
    double first = *std::min_element(v.begin(), v.end());
    int count = 1;
    for (; count < 4; ++count) {
      double next = HUGE_VAL;
      for (double value : v) {
        if (value > first && !(std::fabs(value - first) < 1e-6)) next = std::min(next, value);
      }
      if (next == HUGE_VAL) break;
      first = next;
    }
    return count;
  };
  const int spread = std::min(distinct(xs), distinct(ys));
  if (spread < 2) return out;
  const int order = std::min(max_order, n >= 20 && spread >= 4 ? 3 : n >= 12 && spread >= 3 ? 2 : n >= 6 ? 1 : 0);
  const int p = order == 0 ? 1 : order == 1 ? 3 : order == 2 ? 6 : 10;
  const int h = std::min(n, std::max(n / 2 + (p + 1) / 2, static_cast<int>(std::ceil(keep * n))));
  // Window points by their |residual| to `height(j)`, the first h of them in `subset` (in the
  // selection's order, which the next fit sums in) and, for a window of up to 64, in `mask`.
  const bool masked = n <= 64;
  std::vector<Ranked>& by_residual = scratch.by_residual;
  // With `kept_check`, a `subset` that is already the h smallest is left as it is (in `mask`'s
  // place order for the trimmed sum): the step has converged, and no selection is made.
  auto rank = [&](auto height, std::vector<size_t>& subset, uint64_t& mask, bool kept_check = false) {
    by_residual.resize(static_cast<size_t>(n));
    for (int m = 0; m < n; ++m) {
      const size_t j = window[static_cast<size_t>(m)];
      set_ranked(by_residual, static_cast<size_t>(m), std::fabs(points[j].z - height(j)), j);
    }
    if (kept_check && masked && keeps_mask(by_residual, mask)) {
      double trimmed = 0;
      for (const Ranked& r : by_residual) {
        if (mask >> r.position & 1) trimmed += r.residual * r.residual;
      }
      return trimmed;
    }
    std::nth_element(by_residual.begin(), by_residual.begin() + (h - 1), by_residual.end());
    subset.clear();
    mask = 0;
    double trimmed = 0;
    for (int m = 0; m < h; ++m) {
      const Ranked& r = by_residual[static_cast<size_t>(m)];
      subset.push_back(r.index);
      if (masked) mask |= uint64_t{1} << r.position;
      trimmed += r.residual * r.residual;
    }
    return trimmed;
  };
  std::vector<size_t>& chosen = scratch.chosen;
  uint64_t chosen_mask = 0;
  rank([&](size_t j) { return reference[j]; }, chosen, chosen_mask);
  if (order == 0) {
    double mean = 0, ss = 0;
    for (size_t j : chosen) mean += points[j].z;
    mean /= h;
    for (size_t j : chosen) ss += (points[j].z - mean) * (points[j].z - mean);
    out = LooModel{};
    out.ok = true;
    out.prediction = mean;
    out.scale = std::sqrt(ss / std::max(1, h - 1));
    out.near_kept = 4;
    out.gain = 1.0 / h;
    out.dof = std::max(1, h - 1);
    out.polynomial.order = 1;
    out.polynomial.centre = points[i];
    out.polynomial.c[0] = mean;
    return out;
  }
  // Concentration steps from the start subset `from`; the model, with the subset it keeps left in
  // `kept`. A step that keeps the subset it was fitted to has converged: the next would fit the
  // same points again and keep them again (Rousseeuw and Van Driessen's C-steps), so it is not taken.
  std::vector<size_t>& fitted_set = scratch.fitted_set;
  std::vector<size_t>& kept_set = scratch.kept_set;
  std::vector<size_t>& subset = scratch.subset;
  // `tilt`, when given, is the normal of the frame the model is fitted in (fit_tilted_polynomial),
  // about `centre`.
  auto concentrate = [&](const std::vector<size_t>& from, uint64_t subset_mask, std::vector<size_t>& kept,
                         const double (*tilt)[3] = nullptr, const Point3& centre = Point3{}) {
    LooModel result;
    LocalPolynomial model;
    subset.assign(from.begin(), from.end());
    auto fit = [&] {
      return tilt ? fit_tilted_polynomial(points, subset, centre, *tilt, order, model)
                  : fit_local_polynomial(points, subset, points[i], order, model);
    };
    for (int step = 0; step < 4 && fit(); ++step) {
      const uint64_t fitted_mask = subset_mask;
      if (!masked) fitted_set.assign(subset.begin(), subset.end());
      // A tilted model's points without a height under it rank last (height_or_huge).
      const double trimmed =
          rank([&](size_t j) { return model.height_or_huge(points[j].x, points[j].y); }, subset, subset_mask, true);
      // Every field a step sets is set again by the next (the others keep their defaults): no
      // clearing of the whole model first, whose 248 bytes were a twentieth of this function.
      result.ok = true;
      result.prediction = tilt ? model.at(points[i].x, points[i].y) : model.c[0];
      result.scale = std::sqrt(trimmed / std::max(1, h - p));
      result.gain = model.centre_gain;
      result.dof = std::max(1, h - p);
      result.polynomial = model;
      if (masked) {
        if (subset_mask == fitted_mask) break;
        continue;
      }
      kept_set.assign(subset.begin(), subset.end());
      std::sort(fitted_set.begin(), fitted_set.end());
      std::sort(kept_set.begin(), kept_set.end());
      if (kept_set == fitted_set) break;
    }
    kept.assign(subset.begin(), subset.end());
    return result;
  };
  const std::vector<size_t>* kept_subset = &scratch.kept_first;
  out = concentrate(chosen, chosen_mask, scratch.kept_first);
  {
    // A second start, from the h heights nearest the window's median: where outliers crowd a window
    // the filtered reference took them in too, and its start keeps them.
    std::vector<double>& heights = scratch.heights;
    heights.resize(window.size());
    for (size_t m = 0; m < window.size(); ++m) heights[m] = points[window[m]].z;
    const double middle = median_in_place(heights);
    uint64_t start_mask = 0;
    rank([&](size_t) { return middle; }, scratch.start, start_mask);
    const LooModel other = concentrate(scratch.start, start_mask, scratch.kept_second);
    if (other.ok && (!out.ok || other.scale < out.scale)) {
      out = other;
      kept_subset = &scratch.kept_second;
    }
  }
  if (tilt_on_slopes && out.ok && order >= 2) {
    // On a steep flank, the model again in the frame of its own tangent plane at the point, from
    // the subset it kept (see kTiltSlope).
    const LocalPolynomial& upright = out.polynomial;
    const double slope_x = upright.c[1] / upright.scale_x, slope_y = upright.c[2] / upright.scale_y;
    if (std::hypot(slope_x, slope_y) >= kTiltSlope) {
      const double normal[3] = {-slope_x, -slope_y, 1};
      std::vector<size_t>& from = scratch.start;
      from.assign(kept_subset->begin(), kept_subset->end());
      uint64_t from_mask = 0;
      if (masked) {
        for (int m = 0; m < n; ++m) {
          const size_t j = window[static_cast<size_t>(m)];
          if (std::find(from.begin(), from.end(), j) != from.end()) from_mask |= uint64_t{1} << m;
        }
      }
      // About the height the upright model predicts: the point's own reading may be an outlier.
      const Point3 centre{points[i].x, points[i].y, out.prediction};
      std::vector<size_t>& kept_tilted = kept_subset == &scratch.kept_first ? scratch.kept_second : scratch.kept_first;
      const LooModel tilted = concentrate(from, from_mask, kept_tilted, &normal, centre);
      // Only a fitted model is asked how it predicts the nearest neighbours, and only heights its
      // surface has count: where the vertical through a point misses a surface that turns over,
      // its prediction would be no number of the model.
      auto predicts_nearest = [&] {
        double z = 0;
        if (!tilted.polynomial.height(points[i].x, points[i].y, z)) return false;
        size_t near_index[4];
        const size_t count = nearest_four(points, window, i, near_index, scratch.ranked_points);
        size_t near_within = 0;
        for (size_t m = 0; m < count; ++m) {
          const Point3& q = points[near_index[m]];
          near_within += tilted.polynomial.height(q.x, q.y, z) && std::fabs(q.z - z) <= kTiltNearWithin * tilted.scale;
        }
        return near_within >= std::min<size_t>(3, count);
      };
      if (tilted.ok && tilted.scale < kTiltKeep * out.scale && predicts_nearest()) {
        out = tilted;
        kept_subset = &kept_tilted;
      }
    }
  }
  const LocalPolynomial& model = out.polynomial;
  if (out.ok) {
    size_t near_index[4];
    const size_t count = nearest_four(points, window, i, near_index, scratch.ranked_points);
    out.near_worst = count == 4 ? 0 : HUGE_VAL;
    if (misses != nullptr) {
      *misses = WindowMisses{};
      std::vector<std::pair<double, size_t>>& worst = scratch.ranked_points;
      worst.resize(window.size());
      for (size_t m = 0; m < window.size(); ++m) {
        const size_t j = window[m];
        worst[m].first = std::fabs(points[j].z - model.height_or_huge(points[j].x, points[j].y));
        worst[m].second = j;
      }
      const size_t kept = std::min<size_t>(WindowMisses::kWorst, worst.size());
      std::partial_sort(worst.begin(), worst.begin() + static_cast<std::ptrdiff_t>(kept), worst.end(),
                        [](const auto& a, const auto& b) { return a.first > b.first; });
      for (size_t m = 0; m < kept; ++m) {
        misses->worst_residual[m] = worst[m].first;
        misses->worst_index[m] = static_cast<uint32_t>(worst[m].second);
      }
    }
    for (size_t m = 0; m < count; ++m) {
      const size_t j = near_index[m];
      if (std::find(kept_subset->begin(), kept_subset->end(), j) != kept_subset->end()) ++out.near_kept;
      const double residual = std::fabs(points[j].z - model.height_or_huge(points[j].x, points[j].y));
      if (misses != nullptr) misses->near_index[m] = static_cast<uint32_t>(j), misses->near_residual[m] = residual;
      out.near_worst = std::max(out.near_worst, residual);
    }
  }
  return out;
}

}  // namespace dg::host::lts
