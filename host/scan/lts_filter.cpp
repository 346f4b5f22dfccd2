// LTS filtering: neighbourhoods (grid window or nearest points), trimmed means about a reference.
#include "host/scan/lts_filter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>

#include "host/parallel/parallel_for.h"
#include "host/scan/difference_noise.h"
#include "host/scan/local_polynomial.h"
#include "host/scan/neighbours.h"
#include "host/scan/median.h"

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

// Along a row, a column or a diagonal, a point on a sliver of surface between a crease and the
// scan's edge (too thin for any half-plane to hold mostly its own surface) still has neighbours on
// its own surface: one quadratic per side (kLines of them) may vouch for it but never replace it.
// Each side holds up to kLineReach grid neighbours, nearest first, contiguous (a gap ends the
// side); a line model uses the first kLinePoints of them that are not suspected outliers.
constexpr int kLines = 8;
constexpr int kLinePoints = 5;
constexpr long kLineReach = 8;
// The largest extrapolation gain a line may have and still vouch: 4.6 for five points at 1..5
// steps, 7.75 for four at 1..4, 15.8 for five from the second step on.
constexpr double kLineGainMax = 8;
using LineSides = std::array<std::vector<size_t>, kLines>;
// The largest gain a window's prediction may have and still vouch. A whole window's cubic at a
// corner of the scan has 9 to 11, a diagonal half-plane's quadratic there up to 39. Measured over
// the outlier benchmark's 14 seeds: 11 missed and 35 false alarms with this limit, 14 and 34
// without it.
constexpr double kWindowGainMax = 24;
// Rounds of testing the points beside suspects again without them.
constexpr int kSuspectRounds = 4;

// The points of a grid by their cell (ix, iy): a dense array over the cells' box when that is not
// much larger than the points (a scan), else a sorted list searched by halves. A std::map of the
// cells was a tenth of the whole filter's time on a 120,000-point scan.
class GridCells {
 public:
  static constexpr size_t kNone = SIZE_MAX;
  explicit GridCells(const std::vector<std::pair<long, long>>& at) {
    lo_x_ = hi_x_ = at.empty() ? 0 : at[0].first;
    lo_y_ = hi_y_ = at.empty() ? 0 : at[0].second;
    for (const auto& [ix, iy] : at) {
      lo_x_ = std::min(lo_x_, ix), hi_x_ = std::max(hi_x_, ix), lo_y_ = std::min(lo_y_, iy), hi_y_ = std::max(hi_y_, iy);
    }
    const double box = (static_cast<double>(hi_x_ - lo_x_) + 1) * (static_cast<double>(hi_y_ - lo_y_) + 1);
    dense_ = box <= 16.0 * static_cast<double>(at.size()) + 1024;
    if (dense_) {
      width_ = hi_x_ - lo_x_ + 1;
      index_.assign(static_cast<size_t>(box), kNone);
    }
    for (size_t i = 0; i < at.size(); ++i) {
      if (dense_) {
        size_t& slot = index_[offset(at[i].first, at[i].second)];
        if (slot != kNone) duplicate_ = true;
        slot = i;
      } else {
        sorted_.push_back({at[i], i});
      }
    }
    if (!dense_) {
      std::sort(sorted_.begin(), sorted_.end());
      for (size_t k = 1; k < sorted_.size(); ++k) duplicate_ = duplicate_ || sorted_[k].first == sorted_[k - 1].first;
    }
  }
  bool has_duplicate() const { return duplicate_; }
  // The point in cell (ix, iy), or kNone.
  size_t find(long ix, long iy) const {
    if (ix < lo_x_ || ix > hi_x_ || iy < lo_y_ || iy > hi_y_) return kNone;
    if (dense_) return index_[offset(ix, iy)];
    const auto it = std::lower_bound(sorted_.begin(), sorted_.end(), std::make_pair(std::make_pair(ix, iy), size_t{0}));
    return it != sorted_.end() && it->first == std::make_pair(ix, iy) ? it->second : kNone;
  }
  long lo_x() const { return lo_x_; }
  long hi_x() const { return hi_x_; }
  long lo_y() const { return lo_y_; }
  long hi_y() const { return hi_y_; }

 private:
  size_t offset(long ix, long iy) const { return static_cast<size_t>((iy - lo_y_) * width_ + (ix - lo_x_)); }
  long lo_x_ = 0, hi_x_ = 0, lo_y_ = 0, hi_y_ = 0, width_ = 0;
  bool dense_ = false, duplicate_ = false;
  std::vector<size_t> index_;
  std::vector<std::pair<std::pair<long, long>, size_t>> sorted_;
};

bool grid_neighbourhoods(const std::vector<Point3>& points, int window, std::vector<std::vector<size_t>>& out,
                         std::vector<std::vector<size_t>>& rows_and_columns, std::vector<LineSides>& sides) {
  std::vector<double> xs, ys;
  for (const auto& p : points) xs.push_back(p.x), ys.push_back(p.y);
  const double sx = grid_step(xs), sy = grid_step(ys);
  if (!(sx > 0) || !(sy > 0)) return false;
  const double x0 = *std::min_element(xs.begin(), xs.end()), y0 = *std::min_element(ys.begin(), ys.end());
  std::vector<std::pair<long, long>> at(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    at[i] = {std::lround((points[i].x - x0) / sx), std::lround((points[i].y - y0) / sy)};
  }
  const GridCells cell(at);
  if (cell.has_duplicate()) return false;  // two points in one grid cell: not a grid
  const long lo_x = cell.lo_x(), hi_x = cell.hi_x(), lo_y = cell.lo_y(), hi_y = cell.hi_y();
  // The grid's rows and columns in order, for the noise estimate (gaps break the even spacing
  // the estimate asks of each window, so they need no care here). The occupied rows (by y) and
  // columns (by x), each in order along it.
  std::vector<std::vector<size_t>> rows(static_cast<size_t>(hi_y - lo_y + 1)), columns(static_cast<size_t>(hi_x - lo_x + 1));
  {
    std::vector<size_t> by_cell(points.size());
    for (size_t i = 0; i < points.size(); ++i) by_cell[i] = i;
    std::sort(by_cell.begin(), by_cell.end(), [&](size_t a, size_t b) { return at[a] < at[b]; });  // x, then y
    for (size_t i : by_cell) columns[static_cast<size_t>(at[i].first - lo_x)].push_back(i);
    std::sort(by_cell.begin(), by_cell.end(), [&](size_t a, size_t b) {
      return std::make_pair(at[a].second, at[a].first) < std::make_pair(at[b].second, at[b].first);
    });
    for (size_t i : by_cell) rows[static_cast<size_t>(at[i].second - lo_y)].push_back(i);
  }
  rows_and_columns.clear();
  for (auto* lines : {&rows, &columns}) {
    for (auto& sequence : *lines) {
      if (!sequence.empty()) rows_and_columns.push_back(std::move(sequence));
    }
  }
  // Near an edge of the scan the window shifts inward rather than being cut, so that a point at an
  // edge or a corner keeps a full window x window neighbourhood: a cut 3 x 3 corner window leaves a
  // plane on 8 points, whose curvature bias on a 1 mm grid is tens of sigma.
  const long r = window / 2;
  auto start = [r](long index, long lo, long hi) {
    return hi - lo < 2 * r ? lo : std::clamp(index - r, lo, hi - 2 * r);
  };
  out.assign(points.size(), {});
  sides.assign(points.size(), {});
  static const long kStep[kLines][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}, {-1, -1}, {1, 1}, {-1, 1}, {1, -1}};
  for (size_t i = 0; i < points.size(); ++i) {
    for (int d = 0; d < kLines; ++d) {
      for (long t = 1; t <= kLineReach; ++t) {
        const size_t j = cell.find(at[i].first + t * kStep[d][0], at[i].second + t * kStep[d][1]);
        if (j == GridCells::kNone) break;
        sides[i][d].push_back(j);
      }
    }
  }
  for (size_t i = 0; i < points.size(); ++i) {
    const long first_x = start(at[i].first, lo_x, hi_x), first_y = start(at[i].second, lo_y, hi_y);
    for (long y = first_y; y <= first_y + 2 * r; ++y)
      for (long x = first_x; x <= first_x + 2 * r; ++x) {
        const size_t j = cell.find(x, y);
        if (j != GridCells::kNone) out[i].push_back(j);
      }
  }
  return true;
}

// A robust local model fitted without point i: least trimmed squares by concentration steps from
// two starts, the h neighbours nearest to the filter's reference and the h nearest to the window's
// median height, the smaller trimmed scale kept. h is 70 % of the window (at least the maximal
// breakdown [n/2] + [(p+1)/2]): two or three outliers in one window stay out, and the trimmed
// scale stays a usable measure of how well the model describes the rest.
struct LooModel {
  bool ok = false;
  double prediction = 0;  // the model's height at point i
  double scale = 0;       // its trimmed residual scale
  // How many of point i's four nearest neighbours in the window the model kept: a model that trims
  // them describes another surface than the one i is on (across a crease from it).
  int near_kept = 0;
  // The largest |residual| to the model among those four neighbours.
  double near_worst = HUGE_VAL;
  // The prediction's variance in units of the noise variance: the line's extrapolation gain, and
  // for a window's model [(X^T X)^-1]_00 of its trimmed subset (the verdict bounds a window by its
  // scale instead; the split judge, whose point lies at its side's edge, uses it).
  double gain = 0;
  int dof = 1;  // the trimmed residuals' degrees of freedom, h - p (at least 1)
  LocalPolynomial polynomial;  // the model itself (a window's; a constant as a flat plane)
};

// A quadratic in the distance along a line through the points on one side of point i,
// extrapolated to i; ok only with at least four points (one degree of freedom left to measure
// how well the quadratic describes them) and a gain of at most kLineGainMax. Where the scan's noise
// `sigma` explains the quadratic term (|c| within two standard errors), a straight line stands in:
// on a flat sliver whose nearest neighbour is an outlier, the quadratic through the next five
// points extrapolates with a gain of 15.8 and may not vouch, the straight line with 1.8.
LooModel line_model(const std::vector<Point3>& points, const std::vector<size_t>& reach, size_t i,
                    const std::vector<char>& suspect, double sigma) {
  LooModel out;
  std::vector<size_t> side;
  for (size_t j : reach) {
    if (!suspect[j] && side.size() < static_cast<size_t>(kLinePoints)) side.push_back(j);
  }
  const int n = static_cast<int>(side.size());
  if (n < 4) return out;
  // Normal equations of z = a + b t + c t^2 in t (mm from point i), solved by Cramer's rule: the
  // distinct t of at least four points keep them well conditioned.
  double m[3][3] = {}, rhs[3] = {};
  std::vector<double> ts;
  for (size_t j : side) {
    const double t = std::hypot(points[j].x - points[i].x, points[j].y - points[i].y);
    ts.push_back(t);
    const double row[3] = {1, t, t * t};
    for (int a = 0; a < 3; ++a) {
      rhs[a] += row[a] * points[j].z;
      for (int b = 0; b < 3; ++b) m[a][b] += row[a] * row[b];
    }
  }
  auto det3 = [](const double (&q)[3][3]) {
    return q[0][0] * (q[1][1] * q[2][2] - q[1][2] * q[2][1]) - q[0][1] * (q[1][0] * q[2][2] - q[1][2] * q[2][0]) +
           q[0][2] * (q[1][0] * q[2][1] - q[1][1] * q[2][0]);
  };
  const double det = det3(m);
  if (!(std::fabs(det) > 1e-12)) return out;
  double coefficient[3];
  for (int col = 0; col < 3; ++col) {
    double q[3][3];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) q[a][b] = b == col ? rhs[a] : m[a][b];
    coefficient[col] = det3(q) / det;
  }
  double ss = 0;
  for (int k = 0; k < n; ++k) {
    const double t = ts[static_cast<size_t>(k)];
    const double r = points[side[static_cast<size_t>(k)]].z - (coefficient[0] + coefficient[1] * t + coefficient[2] * t * t);
    ss += r * r;
  }
  out.prediction = coefficient[0];
  out.scale = std::sqrt(ss / (n - 3));
  out.near_kept = 4;
  // [(X^T X)^-1]_00, the cofactor over the determinant. Skipped suspects push the points away and
  // the gain up; beyond kLineGainMax the prediction is too loose to vouch for anything.
  out.gain = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) / det;
  // [(X^T X)^-1]_22 for the quadratic term's standard error.
  const double curvature_se = sigma * std::sqrt((m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det);
  if (std::fabs(coefficient[2]) <= 2 * curvature_se) {
    // z = a + b t: [(X^T X)^-1]_00 = sum t^2 / (n sum t^2 - (sum t)^2).
    const double line_det = m[0][0] * m[1][1] - m[0][1] * m[0][1];
    const double a = (m[1][1] * rhs[0] - m[0][1] * rhs[1]) / line_det, b = (m[0][0] * rhs[1] - m[0][1] * rhs[0]) / line_det;
    double line_ss = 0;
    for (int k = 0; k < n; ++k) {
      const double r = points[side[static_cast<size_t>(k)]].z - (a + b * ts[static_cast<size_t>(k)]);
      line_ss += r * r;
    }
    out.prediction = a;
    out.scale = std::sqrt(line_ss / (n - 2));
    out.gain = m[1][1] / line_det;
  }
  out.ok = out.gain <= kLineGainMax;
  return out;
}

// The window's points other than i and those `excluded` marks.
std::vector<size_t> others_in(const std::vector<size_t>& window, size_t i, const std::vector<char>& excluded) {
  std::vector<size_t> out;
  for (size_t j : window) {
    if (j != i && !excluded[j]) out.push_back(j);
  }
  return out;
}

// Up to four of `members`, the nearest to point i in XY, nearest first.
std::vector<size_t> nearest_four(const std::vector<Point3>& points, const std::vector<size_t>& members, size_t i) {
  std::vector<std::pair<double, size_t>> nearest;
  for (size_t j : members) nearest.push_back({std::hypot(points[j].x - points[i].x, points[j].y - points[i].y), j});
  const size_t count = std::min<size_t>(4, nearest.size());
  std::partial_sort(nearest.begin(), nearest.begin() + static_cast<std::ptrdiff_t>(count), nearest.end());
  std::vector<size_t> out;
  for (size_t m = 0; m < count; ++m) out.push_back(nearest[m].second);
  return out;
}

// Which of a window's points its model misses, for the whole window's model only (kept apart from
// LooModel, of which every point holds seventeen): the judge may pass over a suspected neighbour,
// but not a surface beyond a crease.
struct WindowMisses {
  size_t near_index[4] = {};  // point i's four nearest neighbours in the window
  double near_residual[4] = {};  // and their |residuals|
  static constexpr int kWorst = 5;
  size_t worst_index[kWorst] = {};  // the window's points with the largest |residuals|, largest first
  double worst_residual[kWorst] = {};
};

LooModel loo_model(const std::vector<Point3>& points, const std::vector<size_t>& window, size_t i,
                   const std::vector<double>& reference, int max_order, double keep = 0.7,
                   WindowMisses* misses = nullptr) {
  LooModel out;
  const int n = static_cast<int>(window.size());
  if (n < 3) return out;
  // A model needs as many distinct x and y positions as its order plus one; a window on one line
  // (the half-plane beyond a point on the scan's edge) determines no surface and is no evidence.
  std::vector<double> xs, ys;
  for (size_t j : window) xs.push_back(points[j].x), ys.push_back(points[j].y);
  auto distinct = [](std::vector<double>& v) {
    std::sort(v.begin(), v.end());
    return static_cast<int>(std::unique(v.begin(), v.end(), [](double a, double b) { return std::fabs(a - b) < 1e-6; }) - v.begin());
  };
  const int spread = std::min(distinct(xs), distinct(ys));
  if (spread < 2) return out;
  const int order = std::min(max_order, n >= 20 && spread >= 4 ? 3 : n >= 12 && spread >= 3 ? 2 : n >= 6 ? 1 : 0);
  const int p = order == 0 ? 1 : order == 1 ? 3 : order == 2 ? 6 : 10;
  const int h = std::min(n, std::max(n / 2 + (p + 1) / 2, static_cast<int>(std::ceil(keep * n))));
  std::vector<std::pair<double, size_t>> by_residual;
  for (size_t j : window) by_residual.push_back({std::fabs(points[j].z - reference[j]), j});
  std::nth_element(by_residual.begin(), by_residual.begin() + (h - 1), by_residual.end());
  std::vector<size_t> chosen;
  for (int m = 0; m < h; ++m) chosen.push_back(by_residual[static_cast<size_t>(m)].second);
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
  // Concentration steps from a start subset; the model and the subset it keeps.
  // A step that keeps the subset it was fitted to has converged: the next would fit the same
  // points again and keep them again (Rousseeuw and Van Driessen's C-steps), so it is not taken.
  std::vector<size_t> fitted_set, kept_set;
  auto concentrate = [&](std::vector<size_t> subset, std::vector<size_t>& kept) {
    LooModel result;
    LocalPolynomial model;
    for (int step = 0; step < 4 && fit_local_polynomial(points, subset, points[i], order, model); ++step) {
      fitted_set.assign(subset.begin(), subset.end());
      by_residual.clear();
      for (size_t j : window) by_residual.push_back({std::fabs(points[j].z - model.at(points[j].x, points[j].y)), j});
      std::nth_element(by_residual.begin(), by_residual.begin() + (h - 1), by_residual.end());
      subset.clear();
      double trimmed = 0;
      for (int m = 0; m < h; ++m) {
        subset.push_back(by_residual[static_cast<size_t>(m)].second);
        trimmed += by_residual[static_cast<size_t>(m)].first * by_residual[static_cast<size_t>(m)].first;
      }
      result = LooModel{};
      result.ok = true;
      result.prediction = model.c[0];
      result.scale = std::sqrt(trimmed / std::max(1, h - p));
      result.gain = model.centre_gain;
      result.dof = std::max(1, h - p);
      result.polynomial = model;
      kept_set.assign(subset.begin(), subset.end());
      std::sort(fitted_set.begin(), fitted_set.end());
      std::sort(kept_set.begin(), kept_set.end());
      if (kept_set == fitted_set) break;
    }
    kept = subset;
    return result;
  };
  std::vector<size_t> kept_subset;
  out = concentrate(chosen, kept_subset);
  {
    // A second start, from the h heights nearest the window's median: where outliers crowd a window
    // the filtered reference took them in too, and its start keeps them.
    std::vector<double> heights;
    for (size_t j : window) heights.push_back(points[j].z);
    const double middle = median_of(heights);
    by_residual.clear();
    for (size_t j : window) by_residual.push_back({std::fabs(points[j].z - middle), j});
    std::nth_element(by_residual.begin(), by_residual.begin() + (h - 1), by_residual.end());
    std::vector<size_t> start, kept_too;
    for (int m = 0; m < h; ++m) start.push_back(by_residual[static_cast<size_t>(m)].second);
    const LooModel other = concentrate(start, kept_too);
    if (other.ok && (!out.ok || other.scale < out.scale)) {
      out = other;
      kept_subset = kept_too;
    }
  }
  chosen = kept_subset;
  const LocalPolynomial& model = out.polynomial;
  if (out.ok) {
    const std::vector<size_t> nearest = nearest_four(points, window, i);
    out.near_worst = nearest.size() == 4 ? 0 : HUGE_VAL;
    if (misses != nullptr) {
      *misses = WindowMisses{};
      std::vector<std::pair<double, size_t>> worst;
      for (size_t j : window) worst.push_back({std::fabs(points[j].z - model.at(points[j].x, points[j].y)), j});
      const size_t kept = std::min<size_t>(WindowMisses::kWorst, worst.size());
      std::partial_sort(worst.begin(), worst.begin() + static_cast<std::ptrdiff_t>(kept), worst.end(),
                        [](const auto& a, const auto& b) { return a.first > b.first; });
      for (size_t m = 0; m < kept; ++m) misses->worst_residual[m] = worst[m].first, misses->worst_index[m] = worst[m].second;
    }
    for (size_t m = 0; m < nearest.size(); ++m) {
      const size_t j = nearest[m];
      if (std::find(chosen.begin(), chosen.end(), j) != chosen.end()) ++out.near_kept;
      const double residual = std::fabs(points[j].z - model.at(points[j].x, points[j].y));
      if (misses != nullptr) misses->near_index[m] = j, misses->near_residual[m] = residual;
      out.near_worst = std::max(out.near_worst, residual);
    }
  }
  return out;
}

// The outlier test. Each point is predicted without itself from its whole neighbourhood and from
// the four half neighbourhoods on either side of it in x and in y. A point on a crease or a step,
// or at the edge of the scan, lies on the model of at least one side; an outlier on none.
constexpr int kWindows = 9;  // the whole neighbourhood and eight half-planes through the point

struct PointTest {
  LooModel model[kWindows + kLines];
  double residual[kWindows + kLines] = {};
  WindowMisses whole_misses;  // of model[0]
};

PointTest test_point(const std::vector<Point3>& points, const std::vector<size_t>& hood, size_t i,
                     const std::vector<double>& reference, const std::vector<char>& excluded) {
  // Half-planes bounded by the lines through the point along x, y and both diagonals: a crease
  // that crosses the window at any of these angles leaves one of them wholly on the point's side.
  static const double kNormal[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, -1}, {1, -1}, {-1, 1}};
  PointTest t;
  std::vector<size_t> windows[kWindows];
  for (size_t j : hood) {
    if (j == i || excluded[j]) continue;
    windows[0].push_back(j);
    const double dx = points[j].x - points[i].x, dy = points[j].y - points[i].y;
    for (int w = 0; w < 8; ++w) {
      if (kNormal[w][0] * dx + kNormal[w][1] * dy >= -1e-9) windows[w + 1].push_back(j);
    }
  }
  for (int w = 0; w < kWindows; ++w) {
    // The whole neighbourhood, a cubic: at 0.5 um of noise a quadratic's shape error over 5 x 5 mm
    // of the canister's dish is several sigma. A half-plane holds too few points for one.
    t.model[w] = w == 0 ? loo_model(points, windows[w], i, reference, 3, 0.7, &t.whole_misses)
                        : loo_model(points, windows[w], i, reference, 2);
    if (t.model[w].ok) t.residual[w] = points[i].z - t.model[w].prediction;
  }
  return t;
}

// Some window describes its own neighbours: a trimmed scale that noise gives.
bool some_window_describes(const PointTest& t, double sigma) {
  for (int w = 0; w < kWindows; ++w) {
    if (t.model[w].ok && t.model[w].scale <= 2.5 * sigma) return true;
  }
  return false;
}

// Some window of the point straddles a crease: its trimmed scale is beyond what noise gives.
bool near_crease(const PointTest& t, double sigma) {
  for (int w = 0; w < kWindows; ++w) {
    if (t.model[w].ok && t.model[w].scale > 2.5 * sigma) return true;
  }
  return false;
}

// A window cut in two by a straight line, each side with its own robust model: where a crease
// crosses the window (the dome's rim, ringing round a corner of the scan), the whole window and
// every half-plane through the point mix two surfaces, and the point's own surface may hold only a
// sliver of it. Cuts at 16 directions and at 0.5 to 5 grid steps from the point are tried, each
// side needing at least kSplitSide points; the cut whose two trimmed fits leave the smallest pooled
// residual scale wins, chosen without looking at the point itself. Which side the point is on is
// the open question near the cut, so both sides' models come back (the far one extrapolated to the
// point), each with the pooled scale; not ok when no cut is possible.
constexpr size_t kSplitSide = 6;
// A point no window describes is condemned by a cut only beyond this many times its bound on both
// sides: near a curved crease a straight cut leaves shape error of several sigma (measured on the
// dome at 0.5 um: 1.5 times the bound condemned 7 more rim points than 3 times, and caught one more).
constexpr double kSplitCondemnWiden = 3;
struct SplitModels {
  LooModel own, other;
};
SplitModels split_model(const std::vector<Point3>& points, const std::vector<size_t>& hood, size_t i,
                     const std::vector<double>& reference, const std::vector<char>& excluded) {
  std::vector<size_t> members;
  double step = HUGE_VAL;
  for (size_t j : hood) {
    if (j == i || excluded[j]) continue;
    members.push_back(j);
    step = std::min(step, std::hypot(points[j].x - points[i].x, points[j].y - points[i].y));
  }
  SplitModels best;
  double best_score = HUGE_VAL;
  if (members.size() < 2 * kSplitSide || !(step > 0) || !std::isfinite(step)) return best;
  constexpr double kPi = 3.14159265358979323846;
  std::set<std::vector<char>> tried;
  std::vector<size_t> near_side, far_side, best_near;
  std::vector<char> membership(members.size());
  for (int direction = 0; direction < 16; ++direction) {
    const double nx = std::cos(direction * kPi / 8), ny = std::sin(direction * kPi / 8);
    for (double offset_steps : {0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0}) {
      near_side.clear(), far_side.clear();
      for (size_t m = 0; m < members.size(); ++m) {
        const size_t j = members[m];
        const bool near = nx * (points[j].x - points[i].x) + ny * (points[j].y - points[i].y) < offset_steps * step;
        membership[m] = near;
        (near ? near_side : far_side).push_back(j);
      }
      if (near_side.size() < kSplitSide || far_side.size() < kSplitSide) continue;
      if (!tried.insert(membership).second) continue;
      const LooModel own = loo_model(points, near_side, i, reference, 3);
      const LooModel other = loo_model(points, far_side, i, reference, 3);
      if (!own.ok || !other.ok) continue;
      const double score = (own.scale * own.scale * own.dof + other.scale * other.scale * other.dof) / (own.dof + other.dof);
      if (score < best_score) {
        best_score = score;
        best = {own, other};
        best.own.scale = best.other.scale = std::sqrt(score);
        best_near = near_side;
      }
    }
  }
  // A crease is seldom straight (the dome's rim is a circle): the best straight cut is refined by
  // giving each point to the side whose model describes it better and refitting, twice, while the
  // pooled scale shrinks.
  for (int round = 0; round < 2 && best.own.ok; ++round) {
    near_side.clear(), far_side.clear();
    for (size_t j : members) {
      const double to_own = std::fabs(points[j].z - best.own.polynomial.at(points[j].x, points[j].y));
      const double to_other = std::fabs(points[j].z - best.other.polynomial.at(points[j].x, points[j].y));
      (to_own <= to_other ? near_side : far_side).push_back(j);
    }
    if (near_side.size() < kSplitSide || far_side.size() < kSplitSide || near_side == best_near) break;
    const LooModel own = loo_model(points, near_side, i, reference, 3);
    const LooModel other = loo_model(points, far_side, i, reference, 3);
    if (!own.ok || !other.ok) break;
    const double score = (own.scale * own.scale * own.dof + other.scale * other.scale * other.dof) / (own.dof + other.dof);
    if (!(score < best_score)) break;
    best_score = score;
    best = {own, other};
    best.own.scale = best.other.scale = std::sqrt(score);
    best_near = near_side;
  }
  return best;
}

// Two surfaces that meet in a crease make, together, the larger of the two (a ridge: the dome's
// cap standing on its plate) or the smaller (a valley). Started from the best cut's two models, each
// window point goes to the model that is the envelope there and both are refitted; the envelope
// then describes the whole window, the crease's curve included, however it bends across it, and
// predicts the point on whichever side of the crease it lies. A straight or refined cut only says
// which side each point is on by its distances, so a point raised near the crease passes as the
// other surface's continuation; the envelope knows where that surface ends. Not ok where either
// side keeps fewer than kSplitSide points.
struct CreaseModel {
  bool ok = false;
  double prediction = 0;  // the envelope at point i
  double scale = 0;       // trimmed residual scale of the window's points to the envelope
  double gain = 0;        // the active side's [(X^T X)^-1]_00 at point i
  double near_worst = HUGE_VAL;  // the largest |residual| among point i's four nearest neighbours
};
CreaseModel crease_model(const std::vector<Point3>& points, const std::vector<size_t>& hood, size_t i,
                         const std::vector<double>& reference, const std::vector<char>& excluded,
                         const SplitModels& start) {
  CreaseModel best;
  if (!start.own.ok || !start.other.ok) return best;
  const std::vector<size_t> members = others_in(hood, i, excluded);
  std::vector<size_t> side_a, side_b;
  std::vector<double> squares;
  for (bool ridge : {true, false}) {
    auto envelope = [ridge](double a, double b) { return ridge ? std::max(a, b) : std::min(a, b); };
    LooModel a = start.own, b = start.other;
    bool ok = true;
    for (int round = 0; round < 3 && ok; ++round) {
      side_a.clear(), side_b.clear();
      for (size_t j : members) {
        const double za = a.polynomial.at(points[j].x, points[j].y), zb = b.polynomial.at(points[j].x, points[j].y);
        (envelope(za, zb) == za ? side_a : side_b).push_back(j);
      }
      if (side_a.size() < kSplitSide || side_b.size() < kSplitSide) {
        ok = false;
        break;
      }
      a = loo_model(points, side_a, i, reference, 3);
      b = loo_model(points, side_b, i, reference, 3);
      ok = a.ok && b.ok;
    }
    if (!ok) continue;
    squares.clear();
    for (size_t j : members) {
      const double r = points[j].z - envelope(a.polynomial.at(points[j].x, points[j].y), b.polynomial.at(points[j].x, points[j].y));
      squares.push_back(r * r);
    }
    // 90 % kept: the suspects are out already, and a looser trim let an envelope that had settled
    // on a wrong split of its window (a side holding both far corners) pass for one that describes
    // it, with its 14 worst points trimmed away.
    const size_t h = static_cast<size_t>(std::ceil(0.9 * static_cast<double>(squares.size())));
    std::nth_element(squares.begin(), squares.begin() + static_cast<std::ptrdiff_t>(h - 1), squares.end());
    double trimmed = 0;
    for (size_t m = 0; m < h; ++m) trimmed += squares[m];
    const int dof = std::max(1, static_cast<int>(h) - a.polynomial.terms() - b.polynomial.terms());
    const double scale = std::sqrt(trimmed / dof);
    if (best.ok && !(scale < best.scale)) continue;
    const bool a_active = envelope(a.prediction, b.prediction) == a.prediction;
    const std::vector<size_t> nearest = nearest_four(points, members, i);
    best.near_worst = nearest.size() == 4 ? 0 : HUGE_VAL;
    for (size_t j : nearest) {
      const Point3& q = points[j];
      best.near_worst = std::max(best.near_worst, std::fabs(q.z - envelope(a.polynomial.at(q.x, q.y), b.polynomial.at(q.x, q.y))));
    }
    best.ok = true;
    best.prediction = envelope(a.prediction, b.prediction);
    best.scale = scale;
    best.gain = a_active ? a.gain : b.gain;
  }
  return best;
}

// The line models of a point the windows suspect, from neighbours they do not suspect: an outlier
// beside it on the line would otherwise bend the quadratic towards it.
void add_line_models(const std::vector<Point3>& points, const LineSides& sides, size_t i,
                     const std::vector<char>& suspect, double sigma, PointTest& t) {
  for (int d = 0; d < kLines; ++d) {
    LooModel& m = t.model[kWindows + d];
    m = line_model(points, sides[static_cast<size_t>(d)], i, suspect, sigma);
    if (m.ok) t.residual[kWindows + d] = points[i].z - m.prediction;
  }
}

// A whole neighbourhood that is one smooth surface (noise-level scale) and describes all four of
// the point's nearest neighbours within the bound has the point inside its surface: it alone
// judges. Its prediction at its own centre is an interpolation; a half-plane's or a line's at its
// edge is an extrapolation, whose shape error (tens of sigma at 0.5 um on the canister's dish)
// would vouch for an outlier of 20 sigma.
// One of the four that is itself suspected is passed over where the window without its suspects
// is one smooth surface (`smooth_around`, asked only then): two outliers side by side would
// otherwise each spoil the other's whole window and leave both to the looser half-planes and lines.
// Near a crease a suspect may be a false one on a sliver, and passing over it condemned the rim
// point beside it.
bool whole_judges(const PointTest& t, double sigma, double k, const std::vector<char>* suspect = nullptr,
                  const std::function<bool()>& smooth_around = {}) {
  const LooModel& whole = t.model[0];
  if (!whole.ok || whole.scale > 2.5 * sigma || !std::isfinite(whole.near_worst)) return false;
  const double bound = k * std::hypot(sigma, whole.scale);
  int passed_over = 0;
  for (int m = 0; m < 4; ++m) {
    if (t.whole_misses.near_residual[m] <= bound) continue;
    if (suspect == nullptr || !(*suspect)[t.whole_misses.near_index[m]] || ++passed_over > 1) return false;
  }
  if (passed_over == 0) return true;
  // Having passed over a neighbour, the window judges only a point it finds far off (twice the
  // bound): its verdict rests on one neighbour fewer, and a false suspect on a sliver of surface at a
  // crease, passed over, made a rim point 9 sigma off its window's cubic an outlier.
  if (std::fabs(t.residual[0]) <= 2 * bound || !smooth_around()) return false;
  // Every point of the window the model misses by twice the bound must be a suspect too: at a
  // crease the other surface's points are many and mostly not suspected. (Twice: the window's
  // corners lie where the cubic's own error is largest; one at 2.7 sigma of noise was 5.9 off.)
  const WindowMisses& misses = t.whole_misses;
  if (misses.worst_residual[WindowMisses::kWorst - 1] > 2 * bound) return false;
  for (int m = 0; m < WindowMisses::kWorst - 1; ++m) {
    if (misses.worst_residual[m] > 2 * bound && !(*suspect)[misses.worst_index[m]]) return false;
  }
  return true;
}

// Window or line w describes its own points and predicts point i within its bound. A window's
// prediction errs by its noise and by its model's scale; a line's by the noise its extrapolation
// amplifies, with a tighter bound (0.8 k), since a quadratic through five points can half absorb an
// outlier beside it that its scale then hides.
bool vouches(const PointTest& t, int w, double sigma, double k) {
  const LooModel& m = t.model[w];
  // A window whose prediction has a gain beyond kWindowGainMax extrapolates too far to vouch: a
  // cubic over a window at the scan's edge with its suspects left out reached a gain of 30 and a
  // bound of 28 sigma, wide enough to pass an outlier of 18.
  if (!m.ok || m.near_kept < 2 || m.scale > 2.0 * sigma || (w < kWindows && m.gain > kWindowGainMax)) return false;
  const double bound = w < kWindows ? k * std::sqrt(sigma * sigma * (1 + m.gain) + m.scale * m.scale)
                                     : 0.8 * k * sigma * std::sqrt(1 + m.gain);
  return std::fabs(t.residual[w]) <= bound;
}

// Some line model vouches for the point.
bool a_line_vouches(const PointTest& t, double sigma, double k) {
  for (int w = kWindows; w < kWindows + kLines; ++w) {
    if (vouches(t, w, sigma, k)) return true;
  }
  return false;
}

// The verdict on one point given the scan's noise sigma. A window vouches for the point when it
// describes its own neighbours (trimmed scale within 2 sigma: a window that holds too many
// outliers, or straddles a crease, does not, and its prediction is no evidence either way), keeps
// at least two of the point's four nearest neighbours (else it models another surface than the
// point's), and predicts the point within `k` times its noise and scale together. The point is an
// outlier when no window vouches for it but some describe their neighbours; the best-describing
// one's prediction replaces it. Returns that window, or -1 for an inlier.
// `suspect`: the last classification's suspects, which the whole window may pass over where the
// point's wider window is smooth (`smooth_around`).
int verdict(const PointTest& t, double sigma, double k, const std::vector<char>* suspect,
            const std::function<bool()>& smooth_around) {
  if (whole_judges(t, sigma, k, suspect, smooth_around)) return std::fabs(t.residual[0]) <= k * std::hypot(sigma, t.model[0].scale) ? -1 : 0;
  int best = -1;
  for (int w = 0; w < kWindows + kLines; ++w) {
    const LooModel& m = t.model[w];
    if (!m.ok || m.near_kept < 2 || m.scale > 2.0 * sigma) continue;
    if (vouches(t, w, sigma, k)) return -1;
    if (w < kWindows && (best < 0 || m.scale < t.model[best].scale)) best = w;
  }
  // No window vouches and none that describes its neighbours keeps the point's nearest ones: they
  // are outliers too (a cluster of them), and the first window that describes the rest judges.
  for (int w = 0; best < 0 && w < kWindows; ++w) {
    if (t.model[w].ok && t.model[w].scale <= 2.5 * sigma) best = w;
  }
  return best;
}

}  // namespace

LtsResult lts_filter(const std::vector<Point3>& points, const LtsOptions& options) {
  if (options.window < 3 || options.window % 2 == 0) throw std::invalid_argument("--window must be odd and at least 3");
  const int n_max = options.window * options.window;
  if (options.order < 0 || options.order > 2) throw std::invalid_argument("--order must be 0, 1 or 2");
  if (options.h < 0 || options.h > n_max) throw std::invalid_argument("h must be 1.." + std::to_string(n_max));
  // Points on one line in XY (a single scan line, a profile) have no neighbourhood to model a
  // surface on.
  if (points.size() >= 3) {
    double mx = 0, my = 0;
    for (const auto& p : points) mx += p.x, my += p.y;
    mx /= static_cast<double>(points.size()), my /= static_cast<double>(points.size());
    double sxx = 0, syy = 0, sxy = 0;
    for (const auto& p : points) sxx += (p.x - mx) * (p.x - mx), syy += (p.y - my) * (p.y - my), sxy += (p.x - mx) * (p.y - my);
    const double half_trace = 0.5 * (sxx + syy), root = std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
    const double across_mm = std::sqrt(std::max(0.0, half_trace - root) / static_cast<double>(points.size()));
    if (!(across_mm > 1e-6 * std::max(1.0, std::sqrt((half_trace + root) / static_cast<double>(points.size()))))) {
      throw std::invalid_argument("the points lie on one line in XY (a single scan line or a profile): the LTS filter "
                                  "needs points spread over an area; for a profile use `curve`");
    }
  }
  LtsResult result;
  result.z.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) result.z[i] = points[i].z;
  if (points.size() < 3) return result;

  std::vector<std::vector<size_t>> hood;
  std::vector<std::vector<size_t>> rows_and_columns;
  std::vector<LineSides> sides;
  result.gridded = grid_neighbourhoods(points, options.window, hood, rows_and_columns, sides);
  if (!result.gridded) nearest_neighbourhoods(points, static_cast<size_t>(n_max), hood);

  std::vector<double> reference(points.size());
  const unsigned workers = worker_count();
  // Each worker's scratch: (|residual|, neighbour index) pairs, the chosen subset, the window's heights.
  std::vector<std::vector<std::pair<double, size_t>>> by_distance_of(workers);
  std::vector<std::vector<size_t>> chosen_of(workers);
  std::vector<std::vector<double>> values_of(workers);
  parallel_for(points.size(), [&](size_t begin, size_t end, unsigned w) {
    std::vector<double>& values = values_of[w];
    for (size_t i = begin; i < end; ++i) {
      values.clear();
      for (size_t j : hood[i]) values.push_back(points[j].z);
      reference[i] = median_of(values);
    }
  });
  std::vector<double> before(points.size(), HUGE_VAL);  // the output two iterations back
  size_t previous_moved = SIZE_MAX;
  double previous_largest = HUGE_VAL;
  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    // Each point's next estimate reads only the reference, so the points are shared among the
    // cores; the largest change and the count of moves are gathered per worker.
    std::vector<double> largest_of(workers, 0.0);
    std::vector<size_t> moved_of(workers, 0);
    std::vector<double> next(points.size());
    parallel_for(points.size(), [&](size_t begin, size_t end, unsigned w) {
      std::vector<std::pair<double, size_t>>& by_distance = by_distance_of[w];
      std::vector<size_t>& chosen = chosen_of[w];
      // Gathered here and stored once a chunk: workers writing neighbouring slots for every point
      // would share their cache line.
      double largest = 0;
      size_t moved_here = 0;
      for (size_t i = begin; i < end; ++i) {
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
          for (int m = 0; m < h; ++m) chosen.push_back(by_distance[m].second);
        }
      }
      largest = std::max(largest, std::fabs(next[i] - reference[i]));
      moved_here += std::fabs(next[i] - reference[i]) > options.converged_mm;
      }
      largest_of[w] = std::max(largest_of[w], largest);
      moved_of[w] += moved_here;
    });
    const double largest_change = *std::max_element(largest_of.begin(), largest_of.end());
    size_t moved = 0;
    for (size_t m : moved_of) moved += m;
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
    // Longer cycles, or a few windows flipping while the rest has settled: once neither the number
    // of points that move nor the largest move shrinks, more iterations only repeat themselves
    // (seen on 120,701 points: 6,585 moving by up to 5.9 um from the third iteration to the
    // fiftieth, which took three quarters of the filter's time). Stop on the last state, without
    // calling it converged: each alternating state is a trimmed fit of its window. On that scan
    // the last state finds the same 1,194 outliers as fifty iterations; over the outlier
    // benchmark false alarms went from 124 to 126 with it, and to 133 with the mean of two states.
    if (iteration > 3 && moved >= previous_moved && largest_change >= previous_largest) {
      result.alternating = moved;
      break;
    }
    previous_moved = moved;
    previous_largest = largest_change;
  }
  // Outliers: leave-one-out residuals from the whole neighbourhood and its four sides (test_point).
  std::vector<PointTest> tests(points.size());
  std::vector<double> abs_full(points.size());
  std::vector<char> suspect(points.size(), 0);
  parallel_for(points.size(), [&](size_t begin, size_t end, unsigned) {
    for (size_t i = begin; i < end; ++i) {
      tests[i] = test_point(points, hood[i], i, reference, suspect);
      abs_full[i] = std::fabs(tests[i].residual[0]);
    }
  });
  // 1.4826 * MAD of the whole-neighbourhood residuals: the noise of the scan (outliers and model
  // errors at creases are a minority and do not move the median).
  result.sigma_mm = 1.4826 * median_of(abs_full);
  // On a grid the noise comes from fifth differences along rows and columns instead: the local
  // models' residuals also hold their shape errors, which would pass for noise.
  if (result.gridded) {
    const double from_differences = difference_noise_sigma(points, rows_and_columns);
    if (from_differences > 0) result.sigma_mm = from_differences;
  }
  const double limit = std::max(options.outlier_sigmas * result.sigma_mm, 1e-9);
  const double sigma = std::max(result.sigma_mm, 1e-9);
  // Where outliers crowd a window so that none of its parts describes its own points, the test is
  // made on a window two steps wider, where they are fewer among more.
  std::vector<std::vector<size_t>> wide;
  if (result.gridded) {
    std::vector<std::vector<size_t>> unused_lines;
    std::vector<LineSides> unused_sides;
    grid_neighbourhoods(points, options.window + 2, wide, unused_lines, unused_sides);
  }
  // Only a wider window that is one smooth surface as a whole stands in: at a crease the wider
  // window holds more of the other surface, and a sliver point there has its lines instead.
  auto retest = [&](size_t i, const std::vector<char>& excluded) {
    tests[i] = test_point(points, hood[i], i, reference, excluded);
    if (result.gridded && !some_window_describes(tests[i], sigma)) {
      const PointTest wider = test_point(points, wide[i], i, reference, excluded);
      if (wider.model[0].ok && wider.model[0].scale <= 2.5 * sigma) tests[i] = wider;
    }
  };
  if (result.gridded) {
    parallel_for(points.size(), [&](size_t begin, size_t end, unsigned) {
      for (size_t i = begin; i < end; ++i) {
        if (!some_window_describes(tests[i], sigma)) retest(i, suspect);
      }
    });
  }
  // The window whose prediction replaces point i, or -1 for an inlier.
  // `prior`: the suspects of the last classification (none before the first).
  std::vector<char> prior(points.size(), 0);
  auto outlier_window = [&](size_t i) {
    // A cubic that keeps 90 % of the window's unsuspected points within the noise: a crease leaves
    // more than a tenth of it off any one surface. Only a grid has the wider windows; scattered
    // points never pass a neighbour over.
    const std::function<bool()> smooth_around = [&]() {
      if (!result.gridded) return false;
      const LooModel m = loo_model(points, others_in(wide[i], i, prior), i, reference, 3, 0.9);
      return m.ok && m.scale <= 2.5 * sigma;
    };
    const int window = verdict(tests[i], sigma, options.outlier_sigmas, &prior, smooth_around);
    if (window < 0) return -1;
    // The judging window's prediction errs by the noise its gain amplifies: at a corner of the
    // scan a whole window's cubic reaches a gain of 9 to 11, and put a clean point 6 sigma off.
    auto beyond_bound = [&](int w) {
      const LooModel& m = tests[i].model[w];
      const double bound = options.outlier_sigmas * std::sqrt(sigma * sigma * (1 + m.gain) + m.scale * m.scale);
      return std::fabs(tests[i].residual[w]) > std::max(limit, bound);
    };
    if (beyond_bound(window)) return window;
    // Within it, the other windows decide as where no window judges alone: one that vouches clears
    // the point, and one that describes its points and finds the point beyond its own bound
    // condemns it (a whole window at the scan's edge with its suspects left out, gain 11, missed an
    // outlier of 21 sigma that a half-plane of gain 0.7 saw 21 sigma off).
    for (int w = 0; w < kWindows + kLines; ++w) {
      if (w != window && vouches(tests[i], w, sigma, options.outlier_sigmas)) return -1;
    }
    for (int w = 0; w < kWindows; ++w) {
      const LooModel& m = tests[i].model[w];
      if (w == window || !m.ok || m.near_kept < 2 || m.scale > 2.0 * sigma) continue;
      if (beyond_bound(w)) return w;
    }
    return -1;
  };
  // A marked point a line clears may clear the next one along it (a sliver one point wide along
  // the scan's edge), so the lines, which skip the marked points, are asked again until no mark
  // changes. `cleared_by(i)`: whether point i's verdict, with its lines now in its test, clears it.
  auto clear_by_lines = [&](std::vector<char>& marked, const std::function<bool(size_t)>& cleared_by) {
    for (bool changed = result.gridded; changed;) {
      std::vector<size_t> cleared;
      for (size_t i = 0; i < points.size(); ++i) {
        // Only where some window does not describe one surface (a crease crosses it): on a smooth
        // curved part a quadratic along five points has shape error enough to vouch for an outlier
        // that the windows see plainly (seen at the canister's dish: 0.027 mm off over 7 mm).
        if (!marked[i] || !near_crease(tests[i], sigma)) continue;
        add_line_models(points, sides[i], i, marked, sigma, tests[i]);
        if (cleared_by(i)) cleared.push_back(i);
      }
      for (size_t i : cleared) marked[i] = 0;
      changed = !cleared.empty();
    }
  };
  const std::function<bool(size_t)> no_window_condemns = [&](size_t i) { return outlier_window(i) < 0; };
  auto classify = [&]() {
    prior = suspect;
    for (size_t i = 0; i < points.size(); ++i) {
      for (int d = 0; d < kLines; ++d) tests[i].model[kWindows + d] = LooModel{};
      suspect[i] = outlier_window(i) >= 0;
    }
    clear_by_lines(suspect, no_window_condemns);
  };
  classify();
  // Two or three outliers in one window, or a cluster at a crease, can leave no window that
  // describes its neighbours, or bend the one that does: the points beside suspects are tested
  // again without them, until the suspects settle.
  // Only suspects that their whole neighbourhood condemns are left out: one a half-plane condemns
  // may be a point on a sliver at a crease whose neighbours on the sliver need it. Once left out,
  // a point stays out of its neighbours' tests: in a block of outliers each one, tested without
  // the others, cleared another in turn, and the rounds alternated until they ran out.
  std::vector<char> tested_without(points.size(), 0);  // a point's test left some suspect out
  std::vector<char> left_out(points.size(), 0);
  for (int round = 0; round < kSuspectRounds; ++round) {
    const std::vector<char> before_round = suspect;
    for (size_t i = 0; i < points.size(); ++i) left_out[i] = left_out[i] || (suspect[i] && outlier_window(i) == 0);
    parallel_for(points.size(), [&](size_t begin, size_t end, unsigned) {
      for (size_t i = begin; i < end; ++i) {
        bool beside = false;
        for (size_t j : hood[i]) beside = beside || (j != i && left_out[j]);
        if (!beside && !tested_without[i]) continue;
        retest(i, left_out);
        tested_without[i] = beside;
      }
    });
    classify();
    if (suspect == before_round) break;
  }
  // The final verdict on point i and, for an outlier, the height that replaces it.
  auto judge = [&](size_t i, double& prediction) {
    const int window = outlier_window(i);
    bool outlier = window >= 0;
    prediction = outlier ? tests[i].model[window].prediction : 0;
    // Near a crease, a window cut along it has a second say when its two sides describe their
    // points: its own side's model (the point at the side's edge, so its gain widens the bound) may
    // clear a suspect, and where no window describes its neighbours (the point's surface a sliver
    // among another's), a point that neither side's model comes near is condemned.
    const bool undescribed = !some_window_describes(tests[i], sigma);
    // Near a crease, an envelope of two models that describes its window judges alone, both ways:
    // first over the point's own window, then over the wider one where the own one holds too
    // little of one side.
    bool crease_judged = false;
    if (result.gridded && near_crease(tests[i], sigma) && !whole_judges(tests[i], sigma, options.outlier_sigmas)) {
      for (const std::vector<size_t>* around : {&hood[i], &wide[i]}) {
        // Only a window that is not one smooth surface: where outliers crowd a smooth one, the
        // larger or smaller of two fits to the same surface is biased by their noise. A smooth
        // cubic that keeps fewer than two of the point's four nearest neighbours models another
        // surface than the point's, and the envelope is tried: at 10 um of noise one cubic spans
        // the dome's rim within 2.5 sigma, and plate points 0.5 to 0.6 mm low near the corners,
        // where the cap continued past its rim would dip, passed as the cap's.
        const LooModel single = loo_model(points, others_in(*around, i, suspect), i, reference, 3);
        if (single.ok && single.scale <= 2.5 * sigma && single.near_kept >= 2) continue;
        const SplitModels split = split_model(points, *around, i, reference, suspect);
        const CreaseModel crease = crease_model(points, *around, i, reference, suspect, split);
        // A scale up to 2.5 sigma, as for any window that describes its points: the envelope of two
        // cubics bends less sharply than a sphere meeting its plate, and a clean rim point 0.14 mm
        // above the plate (the dome's (3, 26) of seed 4 at 0.5 um) was left to the plate's
        // half-planes when an envelope of 2.15 sigma predicted it to 6.5 sigma.
        if (!crease.ok || crease.scale > 2.5 * sigma) continue;
        const double bound =
            options.outlier_sigmas * std::sqrt(sigma * sigma * (1 + crease.gain) + crease.scale * crease.scale);
        if (crease.near_worst > bound) continue;
        // An envelope that extrapolates further than a line may (the point at its window's edge)
        // only clears, up to twice that gain and within half its bound: the rim point beside the
        // last one, judged again without it, had only such an envelope predicting it to 5.7 sigma.
        if (crease.gain > kLineGainMax) {
          if (outlier && crease.gain <= 2 * kLineGainMax && std::fabs(points[i].z - crease.prediction) <= 0.5 * bound) {
            outlier = false;
            crease_judged = true;
            break;
          }
          continue;
        }
        outlier = std::fabs(points[i].z - crease.prediction) > std::max(bound, limit);
        prediction = crease.prediction;
        crease_judged = true;
        break;
      }
    }
    if (!crease_judged && result.gridded && near_crease(tests[i], sigma) && (outlier || undescribed)) {
      const SplitModels split = split_model(points, wide[i], i, reference, suspect);
      if (split.own.ok && split.own.scale <= 2.0 * sigma && split.other.ok) {
        auto predicts = [&](const LooModel& m, double widen) {
          const double bound = options.outlier_sigmas * std::sqrt(sigma * sigma * (1 + m.gain) + m.scale * m.scale);
          return m.gain <= kLineGainMax && std::fabs(points[i].z - m.prediction) <= widen * std::max(bound, limit);
        };
        if (outlier && predicts(split.own, 1)) outlier = false;
        // The wider window may put its cut on the wrong side of a point just over a crease: at a
        // corner of the dome's scan it held the point with the plate and condemned a rim point
        // 0.36 mm above it, where the point's own window, cut in two, had the cap's side predict it
        // to 1.6 sigma. That side clears too, but only within half its bound: the cut is the best
        // of many, and a side holding two outliers beside the point (the canister's edge) predicted
        // the third to 6 sigma.
        if (outlier) {
          const SplitModels own_window = split_model(points, hood[i], i, reference, suspect);
          if (own_window.own.ok && own_window.own.scale <= 2.0 * sigma && own_window.other.ok &&
              predicts(own_window.own, 0.5)) {
            outlier = false;
          }
        }
        // The far side's model, extrapolated across the cut, clears only: it errs by its shape too.
        const bool near_either = predicts(split.own, kSplitCondemnWiden) || split.other.gain > kLineGainMax ||
                                 predicts(split.other, kSplitCondemnWiden);
        // Condemned only by an own side that predicts the point closely enough to be evidence.
        if (!outlier && !near_either && undescribed && split.own.gain <= kLineGainMax) {
          outlier = true;
          prediction = split.own.prediction;
        }
      }
    }
    return outlier;
  };
  std::vector<char> condemned(points.size(), 0);
  std::vector<double> replacement(points.size(), 0);
  parallel_for(points.size(), [&](size_t begin, size_t end, unsigned) {
    for (size_t i = begin; i < end; ++i) condemned[i] = judge(i, replacement[i]);
  });
  // The crease judges condemn points the windows did not suspect (an outlier on a sliver of the
  // part's other surface); a line along the sliver that read it as one of its points could not
  // vouch for the sliver point beside it, which the half-planes, all of the other surface, then
  // condemned. The lines are asked again without every condemned point, and a point one of them
  // vouches for is judged again. Only clearing: the envelope still judges alone where it
  // describes its window.
  const std::function<bool(size_t)> a_line_clears = [&](size_t i) {
    double unused;
    return a_line_vouches(tests[i], sigma, options.outlier_sigmas) && !judge(i, unused);
  };
  clear_by_lines(condemned, a_line_clears);
  // The crease's judges read windows that still held the outliers only the envelope condemned: an
  // outlier on the rim with such a one beside it was cleared by a cut's side bent towards it. The
  // points they passed near a crease are judged again with every condemned point left out, only
  // to condemn (a second round both ways alternated), and the lines may clear after.
  if (result.gridded) {
    suspect = condemned;
    std::vector<char> newly(points.size(), 0);
    parallel_for(points.size(), [&](size_t begin, size_t end, unsigned) {
      for (size_t i = begin; i < end; ++i) {
        if (!condemned[i] && near_crease(tests[i], sigma)) newly[i] = judge(i, replacement[i]);
      }
    });
    for (size_t i = 0; i < points.size(); ++i) condemned[i] = condemned[i] || newly[i];
    clear_by_lines(condemned, a_line_clears);
  }
  for (size_t i = 0; i < points.size(); ++i) {
    const bool outlier = condemned[i];
    const double prediction = replacement[i];
    if (outlier) {
      result.outliers.push_back({i, points[i].z - prediction});
      reference[i] = prediction;
    }
    // Inliers keep their measured height unless smoothing is asked for: the least-squares fit that
    // follows averages Gaussian noise without the window's curvature bias.
    result.z[i] = options.replace_all || outlier ? reference[i] : points[i].z;
  }
  return result;
}

}  // namespace dg::host
