// Each point's held-out prediction along its row and its column, the intervals it condemns, and
// the runs of new points that split them.
#include "host/scan/adaptive_sampling.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <utility>

#include "host/scan/difference_noise.h"

namespace dg::host {

int SamplingGrid::levels() const {
  int levels = 0;
  while (levels < 12 && step_mm / std::ldexp(1.0, levels + 1) >= min_step_mm * (1 - 1e-9)) ++levels;
  return levels;
}

double SamplingGrid::unit_mm() const { return step_mm / std::ldexp(1.0, levels()); }

namespace {

using Line = std::vector<std::pair<int64_t, double>>;  // sorted (lattice position, z)

// The value of the polynomial through (t[k], z[k]) at `at` (Lagrange's form).
double lagrange(const std::vector<double>& t, const std::vector<double>& z, double at) {
  double sum = 0;
  for (size_t k = 0; k < t.size(); ++k) {
    double w = 1;
    for (size_t m = 0; m < t.size(); ++m) {
      if (m != k) w *= (at - t[m]) / (t[k] - t[m]);
    }
    sum += w * z[k];
  }
  return sum;
}

// |z - prediction| for the point at `index` of a line: a cubic through its nearest two neighbours
// each side (three from one side where the other has one); -1 at the line's ends or on a line of
// fewer than four points.
double held_out_error(const Line& line, size_t index) {
  const size_t n = line.size();
  if (index == 0 || index + 1 == n || n < 4) return -1;
  size_t below = std::min<size_t>(index, 2), above = std::min<size_t>(n - 1 - index, 2);
  while (below + above < 4 && below < index) ++below;
  while (below + above < 4 && above < n - 1 - index) ++above;
  std::vector<double> t, z;
  for (size_t k = index - below; k <= index + above; ++k) {
    if (k == index) continue;
    t.push_back(static_cast<double>(line[k].first));
    z.push_back(line[k].second);
  }
  return std::fabs(line[index].second - lagrange(t, z, static_cast<double>(line[index].first)));
}

// Marks the intervals beside every point of `line` predicted worse than the tolerance, by their
// left end; keeps the worst error and where it was.
void condemn(const Line& line, int64_t across, bool along_y, double tolerance_mm, std::set<int64_t>* left_ends,
             RefinementPlan* plan, const SamplingGrid& grid, double unit_mm) {
  for (size_t k = 0; k < line.size(); ++k) {
    const double e = held_out_error(line, k);
    if (e > plan->worst_mm) {
      plan->worst_mm = e;
      const double along = static_cast<double>(line[k].first) * unit_mm, other = static_cast<double>(across) * unit_mm;
      plan->worst_at = along_y ? Point3{grid.x0_mm + other, grid.y0_mm + along, line[k].second}
                               : Point3{grid.x0_mm + along, grid.y0_mm + other, line[k].second};
    }
    if (e <= tolerance_mm) continue;
    if (k > 0) left_ends->insert(line[k - 1].first);
    if (k + 1 < line.size()) left_ends->insert(line[k].first);
  }
}

// The middles of the condemned intervals of `positions` (sorted), where they are at least two
// lattice units wide; counts the ones that are not.
std::vector<int64_t> middles(const std::vector<int64_t>& positions, const std::set<int64_t>& left_ends, RefinementPlan* plan) {
  std::vector<int64_t> out;
  for (size_t k = 0; k + 1 < positions.size(); ++k) {
    if (!left_ends.count(positions[k])) continue;
    ++plan->intervals_over;
    const int64_t width = positions[k + 1] - positions[k];
    if (width < 2 || width % 2 != 0) {
      ++plan->intervals_at_min;
      continue;
    }
    out.push_back(positions[k] + width / 2);
  }
  return out;
}

// Splits sorted lattice positions into runs of one step.
template <typename Emit>
void runs_of(const std::vector<int64_t>& positions, Emit emit) {
  for (size_t k = 0; k < positions.size();) {
    size_t end = k + 1;
    const int64_t step = end < positions.size() ? positions[end] - positions[k] : 1;
    while (end < positions.size() && positions[end] - positions[end - 1] == step) ++end;
    emit(positions[k], step, static_cast<int>(end - k));
    k = end;
  }
}

}  // namespace

RefinementPlan plan_refinement(const std::vector<Point3>& points, const SamplingGrid& grid, double tolerance_mm,
                               const std::vector<Point3>& also_near) {
  RefinementPlan plan;
  const double unit = grid.unit_mm();
  std::map<int64_t, Line> rows, columns;  // by lattice y, by lattice x
  std::set<std::pair<int64_t, int64_t>> measured;
  for (const Point3& p : points) {
    const double fi = (p.x - grid.x0_mm) / unit, fj = (p.y - grid.y0_mm) / unit;
    const int64_t i = std::llround(fi), j = std::llround(fj);
    // On the lattice to a micrometre: a point elsewhere is no node.
    if (std::fabs(fi - static_cast<double>(i)) * unit > 1e-3 || std::fabs(fj - static_cast<double>(j)) * unit > 1e-3) continue;
    if (!measured.insert({i, j}).second) continue;
    rows[j].push_back({i, p.z});
    columns[i].push_back({j, p.z});
  }
  // The readings' noise, from the rows' fifth differences: at or above a third of the tolerance
  // over the cubic's noise gain, no sampling brings a held-out point within the tolerance.
  {
    std::vector<Point3> xyz;
    std::vector<std::vector<size_t>> sequences;
    for (auto& [j, row] : rows) {
      std::sort(row.begin(), row.end());
      sequences.emplace_back();
      for (const auto& [i, z] : row) {
        sequences.back().push_back(xyz.size());
        xyz.push_back({static_cast<double>(i) * unit, static_cast<double>(j) * unit, z});
      }
    }
    plan.noise_sigma_mm = difference_noise_sigma(xyz, sequences);
    constexpr double kCubicNoiseGain = 1.39;  // sqrt(1 + (1 + 16 + 16 + 1) / 36)
    plan.noise_miss_mm = 3 * kCubicNoiseGain * plan.noise_sigma_mm;
    if (plan.noise_miss_mm >= tolerance_mm) {
      plan.noise_limited = true;
      plan.columns = columns.size();
      plan.rows = rows.size();
      return plan;
    }
  }
  std::set<int64_t> bad_x, bad_y;  // condemned intervals by their left end
  for (auto& [j, row] : rows) {
    std::sort(row.begin(), row.end());
    condemn(row, j, false, tolerance_mm, &bad_x, &plan, grid, unit);
  }
  for (auto& [i, column] : columns) {
    std::sort(column.begin(), column.end());
    condemn(column, i, true, tolerance_mm, &bad_y, &plan, grid, unit);
  }
  std::vector<int64_t> xs, ys;
  for (const auto& [i, column] : columns) xs.push_back(i);
  for (const auto& [j, row] : rows) ys.push_back(j);
  plan.columns = xs.size();
  plan.rows = ys.size();
  // The intervals either side of the column and the row nearest each point the fit named.
  auto beside = [](const std::vector<int64_t>& positions, double at, std::set<int64_t>* left_ends) {
    if (positions.size() < 2 || !std::isfinite(at)) return;
    const auto it = std::lower_bound(positions.begin(), positions.end(), static_cast<int64_t>(std::floor(at)));
    const size_t k = std::min(static_cast<size_t>(it - positions.begin()), positions.size() - 1);
    const size_t nearest = k > 0 && std::fabs(static_cast<double>(positions[k - 1]) - at) < std::fabs(static_cast<double>(positions[k]) - at) ? k - 1 : k;
    if (nearest > 0) left_ends->insert(positions[nearest - 1]);
    if (nearest + 1 < positions.size()) left_ends->insert(positions[nearest]);
  };
  for (const Point3& p : also_near) {
    beside(xs, (p.x - grid.x0_mm) / unit, &bad_x);
    beside(ys, (p.y - grid.y0_mm) / unit, &bad_y);
  }
  const std::vector<int64_t> new_xs = middles(xs, bad_x, &plan), new_ys = middles(ys, bad_y, &plan);
  plan.new_columns = new_xs.size();
  plan.new_rows = new_ys.size();
  std::vector<int64_t> all_xs = xs, all_ys = ys;
  all_xs.insert(all_xs.end(), new_xs.begin(), new_xs.end());
  all_ys.insert(all_ys.end(), new_ys.begin(), new_ys.end());
  std::sort(all_xs.begin(), all_xs.end());
  std::sort(all_ys.begin(), all_ys.end());
  // Every node of the grid the new columns and rows make that is not measured: by column (up the
  // y axis) for the columns, then by row for the rest.
  const std::set<int64_t> fresh_x(new_xs.begin(), new_xs.end());
  auto add = [&plan, &grid, unit](bool along_y, int64_t i, int64_t j, int64_t step, int count) {
    SampleRun run;
    run.along_y = along_y;
    run.x0_mm = grid.x0_mm + static_cast<double>(i) * unit;
    run.y0_mm = grid.y0_mm + static_cast<double>(j) * unit;
    run.step_mm = static_cast<double>(step) * unit;
    run.count = count;
    plan.runs.push_back(run);
    plan.new_points += static_cast<size_t>(count);
  };
  for (int64_t i : new_xs) runs_of(all_ys, [&](int64_t j, int64_t step, int count) { add(true, i, j, step, count); });
  for (int64_t j : all_ys) {
    std::vector<int64_t> missing;
    for (int64_t i : all_xs) {
      if (!fresh_x.count(i) && !measured.count({i, j})) missing.push_back(i);
    }
    runs_of(missing, [&](int64_t i, int64_t step, int count) { add(false, i, j, step, count); });
  }
  // Each run goes towards +x or +y from its start: the next is the one whose start is nearest the
  // end of the last, from the coarse grid's far corner, where its pass ended.
  std::vector<SampleRun> ordered;
  ordered.reserve(plan.runs.size());
  std::vector<bool> taken(plan.runs.size(), false);
  double at_x = grid.x1_mm, at_y = grid.y1_mm;
  for (size_t n = 0; n < plan.runs.size(); ++n) {
    size_t best = 0;
    double best_d = HUGE_VAL;
    for (size_t k = 0; k < plan.runs.size(); ++k) {
      if (taken[k]) continue;
      const double d = std::hypot(plan.runs[k].x0_mm - at_x, plan.runs[k].y0_mm - at_y);
      if (d < best_d) best_d = d, best = k;
    }
    taken[best] = true;
    const SampleRun& run = plan.runs[best];
    at_x = run.x0_mm + (run.along_y ? 0 : (run.count - 1) * run.step_mm);
    at_y = run.y0_mm + (run.along_y ? (run.count - 1) * run.step_mm : 0);
    ordered.push_back(run);
  }
  plan.runs = std::move(ordered);
  return plan;
}

}  // namespace dg::host
