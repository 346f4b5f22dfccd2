// LTS filtering: neighbourhoods (grid window or nearest points), trimmed means about a reference.
#include "host/scan/lts_filter.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "host/scan/local_polynomial.h"
#include "host/scan/neighbours.h"

namespace dg::host {

namespace {

// The grid step along one axis if every value is (close to) a multiple of a common step from the
// smallest one; 0 otherwise.
double grid_step(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end(), [](double a, double b) { return std::fabs(a - b) < 1e-6; }),
               values.end());
  if (values.size() < 2) return 0;
  double step = HUGE_VAL;
  for (size_t i = 1; i < values.size(); ++i) step = std::min(step, values[i] - values[i - 1]);
  for (double v : values) {
    const double k = (v - values[0]) / step;
    if (std::fabs(k - std::round(k)) > 1e-3) return 0;
  }
  return step;
}

bool grid_neighbourhoods(const std::vector<Point3>& points, int window, std::vector<std::vector<size_t>>& out) {
  std::vector<double> xs, ys;
  for (const auto& p : points) xs.push_back(p.x), ys.push_back(p.y);
  const double sx = grid_step(xs), sy = grid_step(ys);
  if (!(sx > 0) || !(sy > 0)) return false;
  const double x0 = *std::min_element(xs.begin(), xs.end()), y0 = *std::min_element(ys.begin(), ys.end());
  std::map<std::pair<long, long>, size_t> cell;
  std::vector<std::pair<long, long>> at(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    at[i] = {std::lround((points[i].x - x0) / sx), std::lround((points[i].y - y0) / sy)};
    if (!cell.emplace(at[i], i).second) return false;  // two points in one grid cell: not a grid
  }
  const long r = window / 2;
  out.assign(points.size(), {});
  for (size_t i = 0; i < points.size(); ++i) {
    for (long dy = -r; dy <= r; ++dy)
      for (long dx = -r; dx <= r; ++dx) {
        const auto it = cell.find({at[i].first + dx, at[i].second + dy});
        if (it != cell.end()) out[i].push_back(it->second);
      }
  }
  return true;
}

double median_of(std::vector<double> v) {
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  return v[mid];
}

}  // namespace

LtsResult lts_filter(const std::vector<Point3>& points, const LtsOptions& options) {
  if (options.window < 3 || options.window % 2 == 0) throw std::invalid_argument("--window must be odd and at least 3");
  const int n_max = options.window * options.window;
  if (options.order < 0 || options.order > 2) throw std::invalid_argument("--order must be 0, 1 or 2");
  if (options.h < 0 || options.h > n_max) throw std::invalid_argument("h must be 1.." + std::to_string(n_max));
  LtsResult result;
  result.z.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) result.z[i] = points[i].z;
  if (points.size() < 3) return result;

  std::vector<std::vector<size_t>> hood;
  result.gridded = grid_neighbourhoods(points, options.window, hood);
  if (!result.gridded) nearest_neighbourhoods(points, static_cast<size_t>(n_max), hood);

  std::vector<double> reference(points.size());
  std::vector<double> values;
  std::vector<std::pair<double, size_t>> by_distance;  // (|residual|, neighbour index)
  std::vector<size_t> chosen;
  std::vector<double> local_sigma(points.size(), 0.0);  // the trimmed residual scale at each point
  for (size_t i = 0; i < points.size(); ++i) {
    values.clear();
    for (size_t j : hood[i]) values.push_back(points[j].z);
    reference[i] = median_of(values);
  }
  std::vector<double> before(points.size(), HUGE_VAL);  // the output two iterations back
  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    double largest_change = 0;
    std::vector<double> next(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      const int n = static_cast<int>(hood[i].size());
      // A truncated window (an edge or a corner of the scan) cannot carry a quadratic robustly: with
      // 9 points a 6-term model fits its own noise. Use a plane below 4/5 of a full window and a
      // constant below 9 points.
      const int order = n >= (4 * n_max) / 5 ? options.order : n >= 9 ? std::min(options.order, 1) : 0;
      // Maximal breakdown: h = [n/2] + [(p+1)/2], p = 1 (constant), 3 (plane) or 6 (quadratic).
      const int p = order == 0 ? 1 : order == 1 ? 3 : 6;
      const int h = options.h > 0 ? std::min(options.h, n) : std::min(n, n / 2 + (p + 1) / 2);
      by_distance.clear();
      // The reference signal at this point: the window's median in the first pass, this point's
      // previous output after that (Koivunen and Bajcsy 1992: "the output from previous iteration is used as a
      // reference signal for the next iteration").
      for (size_t j : hood[i]) by_distance.push_back({std::fabs(points[j].z - reference[i]), j});
      std::nth_element(by_distance.begin(), by_distance.begin() + (h - 1), by_distance.end());
      double mean = 0;
      for (int m = 0; m < h; ++m) mean += points[by_distance[m].second].z;
      mean /= h;
      next[i] = mean;
      if (order > 0) {
        chosen.clear();
        for (int m = 0; m < h; ++m) chosen.push_back(by_distance[m].second);
        LocalPolynomial model;
        // Concentration steps: keep the h smallest residuals to the model and refit; never increases
        // the trimmed sum of squares, and two or three steps settle it. A subset that does not
        // determine the model keeps the trimmed mean.
        for (int step = 0; step < 4 && fit_local_polynomial(points, chosen, points[i], order, model); ++step) {
          next[i] = model.c[0];
          by_distance.clear();
          for (size_t j : hood[i]) {
            const double r = points[j].z - model.at(points[j].x, points[j].y);
            by_distance.push_back({std::fabs(r), j});
          }
          std::nth_element(by_distance.begin(), by_distance.begin() + (h - 1), by_distance.end());
          chosen.clear();
          double trimmed = 0;
          for (int m = 0; m < h; ++m) {
            chosen.push_back(by_distance[m].second);
            trimmed += by_distance[m].first * by_distance[m].first;
          }
          local_sigma[i] = std::sqrt(trimmed / std::max(1, h - p));
        }
      }
      largest_change = std::max(largest_change, std::fabs(next[i] - reference[i]));
    }
    // Heights quantised by the gauge make ties, and a tie can make a window alternate between two
    // trimmed subsets for ever (seen on a 1 um-resolution scan: one point swinging by 3.9 um). Two
    // steps back equal to the new output is a fixed point of the two-step map: settle on the mean
    // of the two states and call it converged.
    bool two_cycle = iteration > 2;
    for (size_t i = 0; two_cycle && i < points.size(); ++i) two_cycle = std::fabs(next[i] - before[i]) <= options.converged_mm;
    before.swap(reference);
    reference.swap(next);
    result.iterations = iteration;
    if (two_cycle && largest_change > options.converged_mm) {
      for (size_t i = 0; i < points.size(); ++i) reference[i] = 0.5 * (reference[i] + before[i]);
      result.converged = true;
      break;
    }
    if (iteration > 1 && largest_change <= options.converged_mm) {
      result.converged = true;
      break;
    }
  }
  // Outliers: residuals beyond outlier_sigmas robust standard deviations (1.4826 * MAD).
  std::vector<double> abs_residual(points.size());
  for (size_t i = 0; i < points.size(); ++i) abs_residual[i] = std::fabs(points[i].z - reference[i]);
  result.sigma_mm = 1.4826 * median_of(abs_residual);
  const double limit = std::max(options.outlier_sigmas * result.sigma_mm, 1e-9);
  for (size_t i = 0; i < points.size(); ++i) {
    // Where the local model does not describe the window (a crease, a step, a one-sided window on a
    // steep flank) its residual is no evidence against the point: it must also stand out against
    // the model's own trimmed scale there.
    const bool outlier = abs_residual[i] > limit && abs_residual[i] > options.outlier_sigmas * 3.0 * local_sigma[i];
    if (outlier) result.outliers.push_back({i, points[i].z - reference[i]});
    // Inliers keep their measured height unless smoothing is asked for: the least-squares fit that
    // follows averages Gaussian noise without the window's curvature bias.
    result.z[i] = options.replace_all || outlier ? reference[i] : points[i].z;
  }
  return result;
}

}  // namespace dg::host
