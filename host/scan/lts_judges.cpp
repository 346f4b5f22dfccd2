// The LTS filter's outlier judges over a point's windows, lines, cuts and envelopes.
#include "host/scan/lts_judges.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace dg::host::lts {

const LooFit PointModels::kUnfitted{};

PointModels& PointModels::operator=(const PointModels& other) {
  if (this == &other) return *this;
  whole_ = other.whole_;
  halves_ = other.halves_ ? std::make_unique<Block>(*other.halves_) : nullptr;
  lines_ = other.lines_ ? std::make_unique<Block>(*other.lines_) : nullptr;
  return *this;
}

LooFit& PointModels::set(int w) {
  if (w == 0) return whole_;
  std::unique_ptr<Block>& block = w < kWindows ? halves_ : lines_;
  if (!block) block = std::make_unique<Block>();
  return (*block)[static_cast<size_t>(w < kWindows ? w - 1 : w - kWindows)];
}

namespace {

// The whole window's bound on a point: k times the noise and the window's trimmed scale together.
double whole_bound(const LooFit& whole, double sigma, double k) { return k * std::hypot(sigma, whole.scale); }

// A line's bound on a point: the noise its extrapolation amplifies, at 0.8 k (see vouches()).
double line_bound(const LooFit& line, double sigma, double k) { return 0.8 * k * sigma * std::sqrt(1 + line.gain); }

// A window describes its own points: it keeps `nearest_kept` of the point's four nearest
// neighbours, its trimmed scale is one noise gives (within 2 sigma), and its prediction does not
// extrapolate far (gain within kWindowGainMax).
bool describes_its_points(const LooFit& window, double sigma, int nearest_kept) {
  return window.ok && window.near_kept >= nearest_kept && window.scale <= 2.0 * sigma && window.gain <= kWindowGainMax;
}

// A line describes its own points: it keeps two of the point's four nearest neighbours and its
// trimmed scale is one noise gives. Its gain is not limited: line_bound() widens with it.
bool line_describes(const LooFit& line, double sigma) {
  return line.ok && line.near_kept >= 2 && line.scale <= 2.0 * sigma;
}

// The whole window, an interior one (gain within kInteriorGain) that describes the rest of its
// points (scale within 2 sigma), whichever of the point's nearest neighbours it keeps, puts the point
// beyond kWholeOverrulesWiden times its bound.
bool whole_far_off(const PointTest& t, double sigma, double k) {
  const LooFit& whole = t.model[0];
  return whole.ok && whole.gain <= kInteriorGain && whole.scale <= 2 * sigma &&
         std::fabs(t.residual(0)) > kWholeOverrulesWiden * whole_bound(whole, sigma, k);
}

// Fits point i's windows `first` to `last` (0: the whole neighbourhood, 1 to 8: the half-planes)
// into t, from its neighbours not excluded.
void fit_windows(const std::vector<Point3>& points, IndexSpan hood, size_t i,
                 const std::vector<double>& reference, const std::vector<char>& excluded, int first, int last,
                 PointTest& t) {
  // Half-planes bounded by the lines through the point along x, y and both diagonals: a crease
  // that crosses the window at any of these angles leaves one of them wholly on the point's side.
  std::vector<size_t> windows[kWindows];
  for (size_t j : hood) {
    if (j == i || excluded[j]) continue;
    if (first == 0) windows[0].push_back(j);
    if (last == 0) continue;
    for (int w = 0; w < 8; ++w) {
      if (in_half_plane(points[i], points[j], w)) windows[w + 1].push_back(j);
    }
  }
  for (int w = first; w <= last; ++w) {
    // The whole neighbourhood, a cubic: at 0.5 um of noise a quadratic's shape error over 5 x 5 mm
    // of the canister's dish is several sigma. A half-plane holds too few points for one.
    t.model.set(w) = w == 0 ? loo_model(points, windows[w], i, reference, 3, 0.7, &t.whole_misses, true)
                        : loo_model(points, windows[w], i, reference, 2, 0.7, nullptr, true);
  }
}

}  // namespace

PointTest test_point(const std::vector<Point3>& points, IndexSpan hood, size_t i,
                     const std::vector<double>& reference, const std::vector<char>& excluded, Windows which) {
  PointTest t;
  t.z = points[i].z;
  fit_windows(points, hood, i, reference, excluded, 0, which == Windows::kWholeOnly ? 0 : kWindows - 1, t);
  return t;
}

void add_half_planes(const std::vector<Point3>& points, IndexSpan hood, size_t i,
                     const std::vector<double>& reference, const std::vector<char>& excluded, PointTest& t) {
  fit_windows(points, hood, i, reference, excluded, 1, kWindows - 1, t);
}

bool whole_clears(const PointTest& t, double sigma, double k) {
  return whole_judges(t, sigma, k) && std::fabs(t.residual(0)) <= whole_bound(t.model[0], sigma, k);
}

bool some_window_describes(const PointTest& t, double sigma) {
  for (int w = 0; w < kWindows; ++w) {
    if (t.model[w].ok && t.model[w].scale <= 2.5 * sigma) return true;
  }
  return false;
}

bool near_crease(const PointTest& t, double sigma) {
  for (int w = 0; w < kWindows; ++w) {
    if (t.model[w].ok && t.model[w].scale > 2.5 * sigma) return true;
  }
  return false;
}

SplitModels split_model(const std::vector<Point3>& points, IndexSpan hood, size_t i,
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

CreaseModel crease_model(const std::vector<Point3>& points, IndexSpan hood, size_t i,
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
    best.a = a.polynomial;
    best.b = b.polynomial;
    best.ridge = ridge;
  }
  return best;
}

void add_line_models(const std::vector<Point3>& points, const LineSides& sides, size_t i,
                     const std::vector<char>& suspect, double sigma, PointTest& t) {
  for (int d = 0; d < kLines; ++d) {
    LooFit& m = t.model.set(kWindows + d);
    m = line_model(points, sides[static_cast<size_t>(d)], i, suspect, sigma);
  }
}

bool whole_judges(const PointTest& t, double sigma, double k, const std::vector<char>* suspect,
                  const std::function<bool()>& smooth_around) {
  const LooFit& whole = t.model[0];
  if (!whole.ok || whole.scale > 2.5 * sigma || !std::isfinite(whole.near_worst)) return false;
  const double bound = whole_bound(whole, sigma, k);
  // A cubic that misses three of the window's points by twice its bound, none of them suspected,
  // is not one smooth surface: it has trimmed a crease's other side. At the dome's rim, where the
  // base plate is a strip along the scan's edge, such a cubic was the cap continued below the
  // plate, and condemned a clean plate point 0.2 mm above it.
  int far_unsuspected = 0;
  for (int m = 0; m < WindowMisses::kWorst; ++m) {
    const bool unsuspected = suspect == nullptr || !(*suspect)[t.whole_misses.worst_index[m]];
    far_unsuspected += unsuspected && t.whole_misses.worst_residual[m] > 2 * bound;
  }
  if (far_unsuspected >= 3) return false;
  int passed_over = 0;
  for (int m = 0; m < 4; ++m) {
    if (t.whole_misses.near_residual[m] <= bound) continue;
    if (suspect == nullptr || !(*suspect)[t.whole_misses.near_index[m]] || ++passed_over > 1) return false;
  }
  if (passed_over == 0) return true;
  // Having passed over a neighbour, the window judges only a point it finds far off (twice the
  // bound): its verdict rests on one neighbour fewer, and a false suspect on a sliver of surface at a
  // crease, passed over, made a rim point 9 sigma off its window's cubic an outlier.
  if (std::fabs(t.residual(0)) <= 2 * bound || !smooth_around()) return false;
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

int windows_on_its_surface_condemn(const PointTest& t, double sigma, double k) {
  int condemning = 0;
  for (int w = 0; w < kWindows; ++w) {
    const LooFit& m = t.model[w];
    if (!describes_its_points(m, sigma, 3)) continue;
    condemning += std::fabs(t.residual(w)) > prediction_bound(k, sigma, m.gain, m.scale);
  }
  return condemning;
}

bool whole_overrules(const PointTest& t, double sigma, double k) {
  const LooFit& whole = t.model[0];
  if (!describes_its_points(whole, sigma, 3) || whole.gain > kInteriorGain) return false;
  return std::fabs(t.residual(0)) > kWholeOverrulesWiden * whole_bound(whole, sigma, k);
}

bool vouches(const PointTest& t, int w, double sigma, double k, bool final_judgement) {
  const LooFit& m = t.model[w];
  // A window whose prediction has a gain beyond kWindowGainMax extrapolates too far to vouch: a
  // cubic over a window at the scan's edge with its suspects left out reached a gain of 30 and a
  // bound of 28 sigma, wide enough to pass an outlier of 18.
  const bool describes = w < kWindows ? describes_its_points(m, sigma, 2) : line_describes(m, sigma);
  if (!describes) return false;
  const double bound = w < kWindows ? prediction_bound(k, sigma, m.gain, m.scale) : line_bound(m, sigma, k);
  const bool misses_a_neighbour_far = std::isfinite(m.near_worst) && m.near_worst > kWholeFarMiss * bound;
  if (final_judgement && w == 0 && misses_a_neighbour_far) return false;
  if (std::fabs(t.residual(w)) > bound) return false;
  const bool half_plane = w > 0 && w < kWindows;
  if (m.curved && whole_overrules(t, sigma, k)) return false;
  // A half-plane that misses a nearest neighbour far holds the outliers beside the point: in the
  // final judgement it is no witness against a whole window that describes the rest and puts the
  // point far off, even one that keeps only two of the nearest neighbours (those outliers).
  if (final_judgement && half_plane && misses_a_neighbour_far && whole_far_off(t, sigma, k)) return false;
  return !m.curved || windows_on_its_surface_condemn(t, sigma, k) < kCurvedLineOverruled;
}

bool doubted(const PointTest& t, double sigma, double k) {
  int windows_against = 0, lines_against = 0, lines_for = 0;
  for (int w = 0; w < kWindows + kLines; ++w) {
    const LooFit& m = t.model[w];
    const double off = std::fabs(t.residual(w));
    if (w < kWindows) {
      if (!describes_its_points(m, sigma, 2)) continue;
      const double bound = prediction_bound(k, sigma, m.gain, m.scale);
      if (off <= bound) return false;  // a window that describes its points vouches
      windows_against += off > kDoubtWiden * bound;
    } else if (m.ok && m.near_kept >= 2 && !m.curved) {
      const double bound = line_bound(m, sigma, k);
      lines_for += off <= bound;
      lines_against += off > kDoubtWiden * bound;
    }
  }
  return windows_against >= kDoubtModels && lines_against >= kDoubtModels && lines_for <= 1;
}

bool vouched_only_from_afar(const PointTest& t, double sigma, double k) {
  bool vouched = false;
  for (int w = 0; w < kWindows; ++w) {
    if (!vouches(t, w, sigma, k, true)) continue;
    if (t.model[w].gain <= kFarGain) return false;
    vouched = true;
  }
  return vouched;
}

bool windows_stand_against(const PointTest& t, double sigma, double k) {
  int against = 0;
  for (int w = 0; w < kWindows; ++w) {
    const LooFit& m = t.model[w];
    if (!describes_its_points(m, sigma, 3) || m.gain > kNearGain) continue;
    against += std::fabs(t.residual(w)) > prediction_bound(k, sigma, m.gain, m.scale);
  }
  return against >= kWindowsAgainst;
}

bool lines_stand_against(const PointTest& t, double sigma, double k) {
  int against = 0;
  for (int w = kWindows; w < kWindows + kLines; ++w) {
    const LooFit& line = t.model[w];
    if (!line_describes(line, sigma)) continue;
    const double off = std::fabs(t.residual(w));
    if (off <= line_bound(line, sigma, k)) return false;
    against += off > kLinesAgainstWiden * line_bound(line, sigma, k);
  }
  return against >= kLinesAgainst;
}

bool windows_lean_against(const PointTest& t, double sigma, double k) {
  const LooFit& whole = t.model[0];
  if (!whole.ok || whole.scale > kWholeLeansScale * sigma) return false;
  if (std::fabs(t.residual(0)) <= kWholeLeans * whole_bound(whole, sigma, k)) return false;
  return windows_on_its_surface_condemn(t, sigma, k) >= 1;
}

bool vouched_only_by_untested_lines(const std::vector<Point3>& points, const LineSides& sides,
                                    const std::vector<char>& suspect, const PointTest& t, double sigma, double k) {
  for (int w = 0; w < kWindows; ++w) {
    if (vouches(t, w, sigma, k, true)) return false;
  }
  bool vouched = false;
  for (int d = 0; d < kLines; ++d) {
    if (!vouches(t, kWindows + d, sigma, k, true)) continue;
    vouched = true;
    // The side without its nearest unsuspected point, predicting that point.
    const LineSide& side = sides[static_cast<size_t>(d)];
    LineSide beyond;
    size_t nearest = points.size();
    for (size_t m = 0; m < side.size(); ++m) {
      if (nearest == points.size() && !suspect[side[m]]) {
        nearest = side[m];
      } else {
        beyond.push_back(side[m]);
      }
    }
    if (nearest == points.size()) continue;
    const LooFit back = line_model(points, beyond, nearest, suspect, sigma);
    if (back.ok && std::fabs(points[nearest].z - back.prediction) <= line_bound(back, sigma, k)) return false;
  }
  return vouched;
}

bool a_half_plane_nearly_vouches(const PointTest& t, double sigma, double k) {
  if (!t.model[0].ok || t.model[0].gain > kInteriorGain || whole_overrules(t, sigma, k)) return false;
  const bool far_off_the_whole = whole_far_off(t, sigma, k);
  for (int w = 1; w < kWindows; ++w) {
    const LooFit& m = t.model[w];
    if (!m.ok || m.near_kept < 3 || m.scale > kRoughScale * sigma || m.gain > kWindowGainMax) continue;
    const double bound = prediction_bound(k, sigma, m.gain, m.scale);
    // Not one that misses a nearest neighbour beyond its bound: it holds the outliers beside the point.
    if (far_off_the_whole && std::isfinite(m.near_worst) && m.near_worst > bound) continue;
    if (std::fabs(t.residual(w)) <= kRoughWithin * bound) return true;
  }
  return false;
}

bool condemned_narrowly(const PointTest& t, double sigma, double k) {
  if (!t.model[0].ok || t.model[0].gain > kInteriorGain) return false;
  bool beyond = false;
  for (int w = 0; w < kWindows + kLines; ++w) {
    const LooFit& m = t.model[w];
    const double off = std::fabs(t.residual(w));
    if (w < kWindows) {
      if (!describes_its_points(m, sigma, 2)) continue;
      const double bound = prediction_bound(k, sigma, m.gain, m.scale);
      if (off > kNarrowWiden * bound) return false;
      beyond = beyond || off > bound;
    } else if (m.ok && !m.curved && off > kNarrowWiden * line_bound(m, sigma, k)) {
      return false;
    }
  }
  return beyond;
}

bool outvoted(const PointTest& t, double sigma, double k) {
  int windows_for = 0, lines_for = 0;
  for (int w = 0; w < kWindows + kLines; ++w) {
    if (!vouches(t, w, sigma, k, /*final_judgement=*/true)) continue;
    if (w < kWindows) {
      ++windows_for;
    } else {
      lines_for += !t.model[w].curved;
    }
  }
  return windows_for >= kOutvotingModels && lines_for >= kOutvotingModels;
}

bool unvouched(const PointTest& t, double sigma, double k) {
  bool described = false;
  for (int w = 0; w < kWindows + kLines; ++w) {
    if (vouches(t, w, sigma, k, /*final_judgement=*/true)) return false;
    const LooFit& m = t.model[w];
    described = described || (w < kWindows ? describes_its_points(m, sigma, 2) : line_describes(m, sigma));
  }
  return described;
}

bool a_line_vouches(const PointTest& t, double sigma, double k) {
  for (int w = kWindows; w < kWindows + kLines; ++w) {
    if (vouches(t, w, sigma, k)) return true;
  }
  return false;
}

int verdict(const PointTest& t, double sigma, double k, const std::vector<char>* suspect,
            const std::function<bool()>& smooth_around, bool final_judgement) {
  if (whole_judges(t, sigma, k, suspect, smooth_around)) return std::fabs(t.residual(0)) <= whole_bound(t.model[0], sigma, k) ? -1 : 0;
  int best = -1;
  for (int w = 0; w < kWindows + kLines; ++w) {
    const LooFit& m = t.model[w];
    if (!m.ok || m.near_kept < 2 || m.scale > 2.0 * sigma) continue;
    if (vouches(t, w, sigma, k, final_judgement)) return -1;
    if (w < kWindows && (best < 0 || m.scale < t.model[best].scale)) best = w;
  }
  // No window vouches and none that describes its neighbours keeps the point's nearest ones: they
  // are outliers too (a cluster of them), and the first window that describes the rest judges.
  for (int w = 0; best < 0 && w < kWindows; ++w) {
    if (t.model[w].ok && t.model[w].scale <= 2.5 * sigma) best = w;
  }
  return best;
}

}  // namespace dg::host::lts
