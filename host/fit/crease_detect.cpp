// Crease and step detection from slope changes along lines, aligned across lines.
#include "host/fit/crease_detect.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "host/scan/median.h"

namespace dg::host {
namespace {

struct Sample {
  double t_mm;   // position along the sequence
  double z;      // height
  double param;  // the surface parameter in this direction
};

// Parameters of the samples where the slope turns sharply (see detect_creases).
void sequence_candidates(std::vector<Sample> seq, double sigma, std::vector<double>& out) {
  std::sort(seq.begin(), seq.end(), [](const Sample& a, const Sample& b) { return a.t_mm < b.t_mm; });
  const size_t n = seq.size();
  if (n < 5) return;
  std::vector<double> turn(n, 0.0), noise(n, 0.0);
  for (size_t k = 1; k + 1 < n; ++k) {
    const double h1 = seq[k].t_mm - seq[k - 1].t_mm, h2 = seq[k + 1].t_mm - seq[k].t_mm;
    if (!(h1 > 0) || !(h2 > 0)) return;  // repeated positions: not a line to read slopes from
    turn[k] = (seq[k + 1].z - seq[k].z) / h2 - (seq[k].z - seq[k - 1].z) / h1;
    // The turning's noise for independent heights of standard deviation sigma.
    noise[k] = sigma * std::sqrt(1 / (h1 * h1) + (1 / h1 + 1 / h2) * (1 / h1 + 1 / h2) + 1 / (h2 * h2));
  }
  for (size_t k = 1; k + 1 < n; ++k) {
    std::vector<double> around;
    for (size_t j = k > 6 ? k - 6 : 1; j <= std::min(n - 2, k + 6); ++j) {
      if (j + 1 < k || j > k + 1) around.push_back(std::fabs(turn[j]));
    }
    const double threshold = std::max({8 * noise[k], 4 * median_of(around), 1e-9});
    if (std::fabs(turn[k]) > threshold) out.push_back(seq[k].param);
  }
}

// Candidates that line up across at least half of the sequences become creases.
std::vector<double> aligned(const std::vector<std::pair<size_t, double>>& candidates, size_t sequences,
                            double step) {
  std::vector<std::pair<double, size_t>> sorted;
  for (const auto& [sequence, param] : candidates) sorted.push_back({param, sequence});
  std::sort(sorted.begin(), sorted.end());
  std::vector<double> creases;
  size_t start = 0;
  while (start < sorted.size()) {
    size_t end = start + 1;
    while (end < sorted.size() && sorted[end].first - sorted[end - 1].first < 0.5 * step) ++end;
    // A cluster: one position, give or take rounding. Count the sequences that have it.
    std::vector<size_t> lines;
    for (size_t i = start; i < end; ++i) lines.push_back(sorted[i].second);
    std::sort(lines.begin(), lines.end());
    lines.erase(std::unique(lines.begin(), lines.end()), lines.end());
    if (lines.size() >= 3 && 2 * lines.size() >= sequences) {
      double sum = 0;
      for (size_t i = start; i < end; ++i) sum += sorted[i].first;
      creases.push_back(sum / static_cast<double>(end - start));
    }
    start = end;
  }
  return creases;
}

std::vector<double> direction_creases(const std::map<long long, std::vector<size_t>>& sequences, const PointCloud& cloud,
                                      const Parameters& params, bool along_u, double sigma) {
  std::vector<std::pair<size_t, double>> candidates;
  std::vector<double> params_seen;
  size_t index = 0, used = 0;
  for (const auto& [key, members] : sequences) {
    std::vector<Sample> seq;
    for (size_t i : members) {
      const Point3& p = cloud.points[i];
      const double param = along_u ? params.uv[i].u : params.uv[i].v;
      const double t = params.kind == Parameterization::kTableXy ? (along_u ? p.x : p.y) : param;
      seq.push_back({t, p.z, param});
      params_seen.push_back(param);
    }
    if (seq.size() >= 5) ++used;
    std::vector<double> found;
    sequence_candidates(seq, sigma, found);
    for (double f : found) candidates.push_back({index, f});
    ++index;
  }
  if (used < 3) return {};
  std::sort(params_seen.begin(), params_seen.end());
  params_seen.erase(std::unique(params_seen.begin(), params_seen.end()), params_seen.end());
  std::vector<double> steps;
  for (size_t i = 1; i < params_seen.size(); ++i) steps.push_back(params_seen[i] - params_seen[i - 1]);
  const double step = median_of(steps);
  if (!(step > 0)) return {};
  return aligned(candidates, used, step);
}

}  // namespace

Creases detect_creases(const PointCloud& cloud, const Parameters& params, double noise_sigma_mm) {
  Creases out;
  if (!cloud.line) return out;
  std::map<long long, std::vector<size_t>> lines, columns;
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    lines[(*cloud.line)[i]].push_back(i);
    // Columns of a grid: points of equal x, to the nanometre.
    if (params.kind == Parameterization::kTableXy) columns[std::llround(cloud.points[i].x * 1e6)].push_back(i);
  }
  out.u = direction_creases(lines, cloud, params, true, noise_sigma_mm);
  if (params.kind == Parameterization::kTableXy) out.v = direction_creases(columns, cloud, params, false, noise_sigma_mm);
  return out;
}

std::vector<double> with_crease_knots(std::vector<double> knots, const std::vector<double>& creases, int degree) {
  for (double c : creases) {
    if (!(c > 0 && c < 1)) continue;
    // Multiplicity `degree` in all: a knot already there counts, and one more would break the surface.
    const auto present = std::count(knots.begin(), knots.end(), c);
    for (long k = present; k < degree; ++k) knots.push_back(c);
  }
  std::sort(knots.begin(), knots.end());
  return knots;
}

}  // namespace dg::host
