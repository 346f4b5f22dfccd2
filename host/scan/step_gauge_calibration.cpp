// The gauge's scale from a step gauge: its tops found as levels of the readings, then a straight
// line through their heights against the certificate's.
#include "host/scan/step_gauge_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "host/scan/certificate_csv.h"

namespace dg::host {

namespace {

constexpr double kLevelGapMm = 0.2;   // heights further apart than this are two levels
constexpr size_t kMinLevelPoints = 10;
constexpr double kEdgeMm = 0.7;       // a step's readings this close to its ends may be its wall's
constexpr double kMinStepMm = 0.5;    // certified steps closer in height could swap under a scale error

}  // namespace

std::vector<StepLevel> measure_steps(const PointCloud& scan, const std::vector<double>& certified, const std::string& name,
                                     const TableCalibration* map) {
  if (certified.size() < 2) throw CalibrationError(name + ": a step gauge needs at least 2 certified steps");
  std::vector<double> by_height = certified;
  std::sort(by_height.begin(), by_height.end());
  for (size_t k = 1; k < by_height.size(); ++k) {
    if (by_height[k] - by_height[k - 1] < kMinStepMm) {
      throw CalibrationError(name + ": two certified steps lie closer than 0.5 mm in height; they cannot be told apart");
    }
  }
  std::vector<size_t> order(scan.points.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return scan.points[a].z < scan.points[b].z; });
  // Levels: runs of sorted heights without a gap.
  std::vector<std::vector<size_t>> levels;
  for (size_t k = 0; k < order.size(); ++k) {
    if (k == 0 || scan.points[order[k]].z - scan.points[order[k - 1]].z > kLevelGapMm) levels.emplace_back();
    levels.back().push_back(order[k]);
  }
  levels.erase(std::remove_if(levels.begin(), levels.end(), [](const std::vector<size_t>& l) { return l.size() < kMinLevelPoints; }),
               levels.end());
  char words[256];
  if (levels.size() != certified.size() + 1) {
    std::snprintf(words, sizeof words, ": the readings fall into %zu levels; the plate and the certificate's %zu steps make %zu: "
                  "scan the steps' tops and the plate beside them (--x, --y)",
                  levels.size(), certified.size(), certified.size() + 1);
    throw CalibrationError(name + words);
  }
  // The steps' direction: the principal axis of their tops' centres (any sign), and across it.
  double mx = 0, my = 0;
  std::vector<std::pair<double, double>> centre;
  for (size_t l = 1; l < levels.size(); ++l) {
    double sx = 0, sy = 0;
    for (size_t k : levels[l]) sx += scan.points[k].x, sy += scan.points[k].y;
    centre.push_back({sx / static_cast<double>(levels[l].size()), sy / static_cast<double>(levels[l].size())});
    mx += centre.back().first / static_cast<double>(certified.size()), my += centre.back().second / static_cast<double>(certified.size());
  }
  double cxx = 0, cxy = 0, cyy = 0;
  for (const auto& [x, y] : centre) cxx += (x - mx) * (x - mx), cxy += (x - mx) * (y - my), cyy += (y - my) * (y - my);
  const double angle = 0.5 * std::atan2(2 * cxy, cxx - cyy);
  const double dx = std::cos(angle), dy = std::sin(angle);
  auto along = [&](const Point3& p) { return p.x * dx + p.y * dy; };
  auto across = [&](const Point3& p) { return -p.x * dy + p.y * dx; };
  // The mean and the u of the readings in `level` inside [s0, s1] along and [t0, t1] across.
  struct Mean {
    double z = 0, x = 0, u = 0;
    size_t n = 0;
  };
  auto mean_of = [&](const std::vector<size_t>& level, double s0, double s1, double t0, double t1) {
    double sum = 0, sum_sq = 0, sum_x = 0, map_u = 0;
    Mean m;
    for (size_t k : level) {
      const Point3& p = scan.points[k];
      const double s = along(p), t = across(p);
      if (s < s0 || s > s1 || t < t0 || t > t1) continue;
      sum += p.z, sum_sq += p.z * p.z, sum_x += p.x, ++m.n;
      if (map != nullptr && map->covers(p.x, p.y)) map_u = std::fmax(map_u, map->u_at(p.x, p.y));
    }
    if (m.n < 2) return m;
    m.z = sum / static_cast<double>(m.n);
    m.x = sum_x / static_cast<double>(m.n);
    const double variance = std::fmax(0.0, (sum_sq - sum * m.z) / static_cast<double>(m.n - 1));
    // The map's error under a top is one value for all its readings (its nodes are few there): it
    // does not average out, and the largest node's u is what it may be.
    m.u = std::sqrt(variance / static_cast<double>(m.n) + map_u * map_u);
    return m;
  };
  const std::vector<size_t>& plate = levels.front();
  std::vector<StepLevel> steps;
  for (size_t l = 1; l < levels.size(); ++l) {
    double s0 = 1e300, s1 = -1e300, t0 = 1e300, t1 = -1e300;
    for (size_t k : levels[l]) {
      const double s = along(scan.points[k]), t = across(scan.points[k]);
      s0 = std::fmin(s0, s), s1 = std::fmax(s1, s), t0 = std::fmin(t0, t), t1 = std::fmax(t1, t);
    }
    const Mean top = mean_of(levels[l], s0 + kEdgeMm, s1 - kEdgeMm, t0 + kEdgeMm, t1 - kEdgeMm);
    if (top.n < kMinLevelPoints) {
      std::snprintf(words, sizeof words, ": the step around (%.3f, %.3f) mm has %zu readings away from its edges; scan it at "
                    "1 mm or finer, across its whole width", centre[l - 1].first, centre[l - 1].second, top.n);
      throw CalibrationError(name + words);
    }
    // The plate beside the top: over the top's inner span along the steps, on either side across.
    Mean beside = mean_of(plate, s0 + kEdgeMm, s1 - kEdgeMm, t1 + kEdgeMm, 1e300);
    if (beside.n < kMinLevelPoints) beside = mean_of(plate, s0 + kEdgeMm, s1 - kEdgeMm, -1e300, t0 - kEdgeMm);
    if (beside.n < kMinLevelPoints) {
      std::snprintf(words, sizeof words, ": the step around (%.3f, %.3f) mm has %zu readings of the plate beside it; scan the "
                    "plate beside every step, a few millimetres of it", centre[l - 1].first, centre[l - 1].second, beside.n);
      throw CalibrationError(name + words);
    }
    StepLevel step;
    step.points = top.n + beside.n;
    step.height_mm = top.z - beside.z;
    step.x_mm = centre[l - 1].first, step.y_mm = centre[l - 1].second;
    step.u_mm = std::hypot(top.u, beside.u);
    steps.push_back(step);
  }
  // The levels are in height order; so, sorted, are the certified steps: the k-th of each match
  // (a scale error 2 % off moves no step past a neighbour 0.5 mm away up to 25 mm).
  std::vector<size_t> rank(certified.size());
  for (size_t k = 0; k < rank.size(); ++k) rank[k] = k;
  std::sort(rank.begin(), rank.end(), [&](size_t a, size_t b) { return certified[a] < certified[b]; });
  std::vector<StepLevel> out(certified.size());
  for (size_t k = 0; k < rank.size(); ++k) out[rank[k]] = steps[k];
  return out;
}

GaugeScale calibrate_gauge_scale(const PointCloud& scan, const std::vector<double>& certified, const std::string& name,
                                 const TableCalibration* map) {
  GaugeScale out;
  out.steps = measure_steps(scan, certified, name, map);
  char words[256];
  // h = a + b H, weighted by 1 / u^2 (u at least a nanometre: a noise-free simulation).
  double sw = 0, sh = 0, sH = 0;
  for (size_t k = 0; k < certified.size(); ++k) {
    const double w = 1 / std::pow(std::fmax(out.steps[k].u_mm, 1e-6), 2);
    sw += w, sh += w * out.steps[k].height_mm, sH += w * certified[k];
  }
  const double mean_h = sh / sw, mean_H = sH / sw;
  double sxx = 0, sxy = 0, span = 0;
  for (size_t k = 0; k < certified.size(); ++k) {
    const double w = 1 / std::pow(std::fmax(out.steps[k].u_mm, 1e-6), 2);
    sxx += w * (certified[k] - mean_H) * (certified[k] - mean_H);
    sxy += w * (certified[k] - mean_H) * (out.steps[k].height_mm - mean_h);
    span = std::fmax(span, std::fabs(certified[k] - certified[0]));
  }
  if (span < 1.0) throw CalibrationError(name + ": the certified steps span less than 1 mm; a scale needs heights further apart");
  const double slope = sxy / sxx;
  double chi2 = 0, ss = 0;
  for (size_t k = 0; k < certified.size(); ++k) {
    const double r = out.steps[k].height_mm - (mean_h + slope * (certified[k] - mean_H));
    ss += r * r;
    chi2 += r * r / std::pow(std::fmax(out.steps[k].u_mm, 1e-6), 2);
  }
  out.residual_rms_mm = std::sqrt(ss / static_cast<double>(certified.size()));
  // The u's stated, unless the heights scatter more about the line than they say (chi^2 per
  // degree of freedom above 1): then that scatter (Birge's ratio).
  const size_t dof = certified.size() - 2;
  const double birge = dof > 0 ? std::fmax(1.0, std::sqrt(chi2 / static_cast<double>(dof))) : 1.0;
  out.scale_ppm = (slope - 1) * 1e6;
  out.u_scale_ppm = birge / std::sqrt(sxx) * 1e6;
  if (std::fabs(out.scale_ppm) > 20000) {
    std::snprintf(words, sizeof words, ": the steps read %+.0f ppm off their certified heights: is the certificate this gauge's, "
                  "its heights in mm?", out.scale_ppm);
    throw CalibrationError(name + words);
  }
  return out;
}

std::vector<double> read_step_certificate(const std::string& path) {
  std::vector<double> out;
  const std::vector<std::vector<double>> rows = read_certificate_rows(path, 1, "a height in mm");
  for (size_t k = 0; k < rows.size(); ++k) {
    if (std::fabs(rows[k][0]) > 1000) throw CalibrationError(path + ": height " + std::to_string(k + 1) + " is not within 1000 mm");
    out.push_back(rows[k][0]);
  }
  if (out.size() < 2) throw CalibrationError(path + ": a step gauge's certificate needs at least 2 steps, it has " + std::to_string(out.size()));
  return out;
}

}  // namespace dg::host
