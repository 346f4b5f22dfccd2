// The LTS judges' properties that the filter's shortcuts rely on.
#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "host/scan/lts_judges.h"

using namespace dg::host::lts;

TEST_GROUP(LtsJudges){};

namespace {

// A window's model that fitted, with its figures.
LooFit fitted(double prediction, double scale, double gain, int near_kept, double near_worst = HUGE_VAL) {
  LooFit m;
  m.ok = true;
  m.prediction = prediction;
  m.scale = scale;
  m.gain = gain;
  m.near_kept = static_cast<int8_t>(near_kept);
  m.near_worst = near_worst;
  return m;
}

}  // namespace

TEST(LtsJudges, AWholeWindowThatJudgesAloneWithoutSuspectsStillJudgesAloneWithAny) {
  // The filter fits a point's eight half-planes only where its whole window, asked without
  // suspects, does not judge alone and clear it: every later verdict asks that window first, with
  // the suspects of the moment. The shortcut is sound only if suspects never take the whole
  // window's say away. Checked over random windows: residuals near and beyond the bound, any
  // suspects, a smooth or a creased wider window.
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double sigma = 1.0, k = 5.0;
  int judged_without = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    PointTest t;
    t.model.set(0).ok = true;
    t.model.set(0).scale = 2.5 * sigma * unit(rng);
    t.model.set(0).near_worst = 1.0;
    const double bound = k * std::hypot(sigma, t.model.set(0).scale);
    t.z = (unit(rng) - 0.5) * 6 * bound;  // model 0 predicts 0
    // Ten window points: four nearest, five worst, drawn from the same ten.
    std::vector<size_t> order(10);
    for (size_t m = 0; m < order.size(); ++m) order[m] = m;
    std::shuffle(order.begin(), order.end(), rng);
    for (int m = 0; m < 4; ++m) {
      t.whole_misses.near_index[m] = order[static_cast<size_t>(m)];
      t.whole_misses.near_residual[m] = unit(rng) < 0.8 ? bound * unit(rng) : bound * (1 + 2 * unit(rng));
    }
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<double> worst;
    for (int m = 0; m < WindowMisses::kWorst; ++m) worst.push_back(3 * bound * unit(rng));
    std::sort(worst.rbegin(), worst.rend());
    for (int m = 0; m < WindowMisses::kWorst; ++m) {
      t.whole_misses.worst_index[m] = order[static_cast<size_t>(m)];
      t.whole_misses.worst_residual[m] = worst[static_cast<size_t>(m)];
    }
    if (!whole_judges(t, sigma, k)) continue;
    ++judged_without;
    std::vector<char> suspect(10);
    for (char& s : suspect) s = unit(rng) < 0.3;
    const bool smooth = unit(rng) < 0.5;
    CHECK(whole_judges(t, sigma, k, &suspect, [smooth] { return smooth; }));
  }
  // The draw must reach the case it checks often enough to mean something.
  CHECK(judged_without > 1000);
}

namespace {

// A point 20 sigma above what its whole window and two half-planes predict, each describing its
// points to the noise and keeping three of the point's four nearest neighbours; and a line from one
// side that predicts it within 2 sigma, with a quadratic's gain of 4.6 (five points at 1..5 steps).
PointTest windows_against_a_line(bool line_curved) {
  const double sigma = 1.0;
  PointTest t;
  t.z = 20 * sigma;
  for (int w : {0, 1, 3}) {
    LooFit& m = t.model.set(w);
    m.ok = true;
    m.prediction = 0;
    m.scale = 0.8 * sigma;
    m.gain = 0.6;
    m.near_kept = 3;
    m.near_worst = sigma;
  }
  // The whole window misses one of the four by far (the one it trimmed), so it does not judge alone.
  t.whole_misses.near_residual[0] = 100 * sigma;
  LooFit& line = t.model.set(kWindows + 2);
  line.ok = true;
  line.prediction = 18 * sigma;
  line.scale = 1.2 * sigma;
  line.gain = 4.6;
  line.near_kept = 4;
  line.curved = line_curved;
  return t;
}

}  // namespace

TEST(LtsJudges, ACurvedLineDoesNotVouchForAPointThreeWindowsOnItsSurfaceCondemn) {
  // On the reference sphere a line's quadratic, extrapolated two steps' worth of curvature to the
  // point, vouched for outliers of 20 and 22 sigma that the windows plainly saw.
  const PointTest t = windows_against_a_line(true);
  LONGS_EQUAL(3, windows_on_its_surface_condemn(t, 1.0, 5.0));
  CHECK_FALSE(vouches(t, kWindows + 2, 1.0, 5.0));
  CHECK_FALSE(a_line_vouches(t, 1.0, 5.0));
  CHECK(verdict(t, 1.0, 5.0, nullptr, {}) >= 0);
}

TEST(LtsJudges, AStraightLineStillVouchesAgainstTheWindows) {
  // Along a plate's sliver at the dome's rim the windows are all of the cap, and the straight line
  // along the sliver is the one model of the point's own surface.
  const PointTest t = windows_against_a_line(false);
  CHECK(vouches(t, kWindows + 2, 1.0, 5.0));
  LONGS_EQUAL(-1, verdict(t, 1.0, 5.0, nullptr, {}));
}

TEST(LtsJudges, TwoCondemningWindowsDoNotOverruleACurvedLine) {
  PointTest t = windows_against_a_line(true);
  t.model.set(0).near_kept = 2;  // the whole window keeps only two of the nearest: maybe another surface
  LONGS_EQUAL(2, windows_on_its_surface_condemn(t, 1.0, 5.0));
  CHECK_FALSE(whole_overrules(t, 1.0, 5.0));
  CHECK(vouches(t, kWindows + 2, 1.0, 5.0));
}

TEST(LtsJudges, AWholeWindowThatPutsThePointFarOffOverrulesACurvedLineAlone) {
  // The sphere's flank at 0.5 um: no half-plane describes its points, and the whole window, which
  // does and interpolates, puts the point beyond twice its bound (20 sigma, bound 6.4).
  PointTest t = windows_against_a_line(true);
  t.model.set(1).near_kept = t.model.set(3).near_kept = 2;
  LONGS_EQUAL(1, windows_on_its_surface_condemn(t, 1.0, 5.0));
  CHECK(whole_overrules(t, 1.0, 5.0));
  CHECK_FALSE(vouches(t, kWindows + 2, 1.0, 5.0));
  // Within twice its bound, or extrapolating (gain over 1), it does not overrule alone.
  t.model.set(0).prediction = 8;
  CHECK_FALSE(whole_overrules(t, 1.0, 5.0));
  CHECK(vouches(t, kWindows + 2, 1.0, 5.0));
  t.model.set(0).prediction = 0;
  t.model.set(0).gain = 1.5;
  CHECK_FALSE(whole_overrules(t, 1.0, 5.0));
  CHECK(vouches(t, kWindows + 2, 1.0, 5.0));
}

TEST(LtsJudges, AHalfPlaneThatMissesANearestNeighbourFarIsOverruledInTheFinalJudgement) {
  // The sphere's flank at 2 um: a half-plane bent by outliers beside the point put it 5 sigma off,
  // within its bound, and missed a clean nearest neighbour by 18 times that bound.
  PointTest t = windows_against_a_line(false);
  LooFit& half = t.model.set(4);
  half.ok = true;
  half.prediction = 18;
  half.scale = 1.0;
  half.gain = 1.0;
  half.near_kept = 2;
  half.near_worst = 224;  // bound 5 sqrt(2 + 1) = 8.7
  CHECK(whole_overrules(t, 1.0, 5.0));
  CHECK_FALSE(vouches(t, 4, 1.0, 5.0, /*final_judgement=*/true));
  // Not while the suspects are sorted out, nor where it predicts its nearest neighbours.
  CHECK(vouches(t, 4, 1.0, 5.0, /*final_judgement=*/false));
  half.near_worst = 20;
  CHECK(vouches(t, 4, 1.0, 5.0, /*final_judgement=*/true));
}

TEST(LtsJudges, AHalfPlaneALittleRougherThanAJudgeThatPredictsThePointCloselyNearlyVouches) {
  // A ring point at a ball's foot: the ball's half-plane (scale 2.04 sigma) predicts it within a
  // ninth of its bound; the whole window (two nearest neighbours kept) does not describe its points.
  PointTest t;
  t.z = 130;
  t.model.set(0) = fitted(108, 2.7, 0.3, 2);
  LooFit& half = t.model.set(2);
  half.ok = true;
  half.prediction = 128.5;
  half.scale = 2.04;
  half.gain = 1.8;
  half.near_kept = 3;  // bound 5 sqrt(2.8 + 2.04^2) = 13.2
  CHECK_FALSE(vouches(t, 2, 1.0, 5.0));
  CHECK(a_half_plane_nearly_vouches(t, 1.0, 5.0));
  // Not beyond half its bound, nor rougher than 2.5 sigma, nor keeping two nearest neighbours only.
  half.prediction = 122;
  CHECK_FALSE(a_half_plane_nearly_vouches(t, 1.0, 5.0));
  half.prediction = 128.5;
  half.scale = 2.6;
  CHECK_FALSE(a_half_plane_nearly_vouches(t, 1.0, 5.0));
  half.scale = 2.04;
  half.near_kept = 2;
  CHECK_FALSE(a_half_plane_nearly_vouches(t, 1.0, 5.0));
  // Nor at the scan's edge, where the whole window extrapolates (gain over 1).
  half.near_kept = 3;
  t.model.set(0).gain = 2;
  CHECK_FALSE(a_half_plane_nearly_vouches(t, 1.0, 5.0));
  t.model.set(0).gain = 0.3;
  CHECK(a_half_plane_nearly_vouches(t, 1.0, 5.0));
  // Nor where the whole window, describing its points, puts the point far off.
  t.model.set(0).scale = 1.0;
  t.model.set(0).near_kept = 4;
  t.model.set(0).prediction = 100;
  CHECK_FALSE(a_half_plane_nearly_vouches(t, 1.0, 5.0));
}

namespace {

// A point 100 sigma above what three windows predict (each describing its points to the noise and
// keeping three of its four nearest neighbours) and three straight lines through or beside it,
// and one more straight line that predicts it: the step gauge's outliers a level's height off,
// with the line along the level above them vouching.
PointTest one_line_against_the_rest() {
  const double sigma = 1.0;
  PointTest t;
  t.z = 100 * sigma;
  for (int w : {0, 3, 4}) {
    LooFit& m = t.model.set(w);
    m.ok = true;
    m.scale = 0.5 * sigma;
    m.gain = 0.5;
    m.near_kept = 3;
  }
  for (int d = 0; d < 4; ++d) {
    LooFit& line = t.model.set(kWindows + d);
    line.ok = true;
    line.gain = 1.1;
    line.near_kept = 4;
    line.prediction = d == 3 ? 99 * sigma : 0;
  }
  return t;
}

}  // namespace

TEST(LtsJudges, APointOneLineVouchesForAgainstThreeWindowsAndThreeLinesIsDoubted) {
  CHECK(doubted(one_line_against_the_rest(), 1.0, 5.0));
}

TEST(LtsJudges, APointAWindowDescribingItsPointsVouchesForIsNotDoubted) {
  PointTest t = one_line_against_the_rest();
  t.model.set(5) = t.model.set(3);
  t.model.set(5).prediction = 99;  // a half-plane of the point's own level
  CHECK_FALSE(doubted(t, 1.0, 5.0));
  // A window that does not describe its points (a crease inside it) is no evidence either way.
  t.model.set(5).scale = 3.0;
  CHECK(doubted(t, 1.0, 5.0));
}

TEST(LtsJudges, APointTwoStraightLinesVouchForIsNotDoubted) {
  // At a step block's corner the lines along the point's own level vouch for it.
  PointTest t = one_line_against_the_rest();
  t.model.set(kWindows + 2).prediction = 99;
  CHECK_FALSE(doubted(t, 1.0, 5.0));
}

TEST(LtsJudges, TwoModelsOfAKindAgainstAPointDoNotMakeADoubt) {
  PointTest t = one_line_against_the_rest();
  t.model.set(4).ok = false;
  CHECK_FALSE(doubted(t, 1.0, 5.0));
  t = one_line_against_the_rest();
  t.model.set(kWindows + 1).curved = true;  // a curved line extrapolates curvature: not counted
  CHECK_FALSE(doubted(t, 1.0, 5.0));
}

namespace {

// A real point on the reference sphere's flank at 1 um (seed 13, (19, 6)): its whole window, a
// cubic interpolating with a gain of 0.34 and describing its points to 1.73 sigma (shape error a
// 1 mm grid leaves), and two half-planes put it 1.04 to 1.43 times beyond their bounds.
PointTest narrowly_off() {
  PointTest t;
  t.z = 0;
  const double predictions[3] = {10.9, -18.2, -13.7}, scales[3] = {1.73, 0.86, 0.86}, gains[3] = {0.34, 4.8, 3.0};
  const int windows[3] = {0, 3, 5};
  for (int n = 0; n < 3; ++n) {
    LooFit& m = t.model.set(windows[n]);
    m.ok = true;
    m.prediction = predictions[n];
    m.scale = scales[n];
    m.gain = gains[n];
    m.near_kept = 3;
  }
  return t;
}

}  // namespace

TEST(LtsJudges, AnInteriorPointNoModelPutsFarBeyondItsBoundIsCondemnedOnlyNarrowly) {
  CHECK(condemned_narrowly(narrowly_off(), 1.0, 5.0));
}

TEST(LtsJudges, APointOneWindowPutsFarOffIsNotCondemnedNarrowly) {
  PointTest t = narrowly_off();
  t.model.set(3).prediction = -40;  // 2.6 times the half-plane's bound
  CHECK_FALSE(condemned_narrowly(t, 1.0, 5.0));
}

TEST(LtsJudges, APointAStraightLinePutsFarOffIsNotCondemnedNarrowly) {
  PointTest t = narrowly_off();
  LooFit& line = t.model.set(kWindows + 1);
  line.ok = true;
  line.gain = 1.1;
  line.near_kept = 4;
  line.prediction = 20;  // 2.4 times the line's bound
  CHECK_FALSE(condemned_narrowly(t, 1.0, 5.0));
  line.curved = true;  // a curved line extrapolates its curvature: no evidence either way
  CHECK(condemned_narrowly(t, 1.0, 5.0));
}

TEST(LtsJudges, APointAtTheScansEdgeIsNotCondemnedNarrowly) {
  // There the whole window extrapolates (gain 5 at the canister's last line), its bound grows with
  // the gain, and an outlier of 20 sigma lay 1.34 times beyond it.
  PointTest t = narrowly_off();
  t.model.set(0).gain = 5.0;
  CHECK_FALSE(condemned_narrowly(t, 1.0, 5.0));
}

TEST(LtsJudges, APointEveryWindowPredictsIsNotCondemnedNarrowly) {
  PointTest t = narrowly_off();
  for (int w : {0, 3, 5}) t.model.set(w).prediction = 1;
  CHECK_FALSE(condemned_narrowly(t, 1.0, 5.0));
}

namespace {

// A plate point at a ball's foot that a crease's envelope condemned 40 sigma low: two half-planes
// of the plate (describing their points, keeping two of its four nearest neighbours) and two
// straight lines along the plate predict it to half a sigma.
PointTest envelope_against_its_surface() {
  PointTest t;
  t.z = 0;
  LooFit& whole = t.model.set(0);  // the whole window, across the foot, misses it
  whole.ok = true;
  whole.scale = 1.5;
  whole.gain = 0.5;
  whole.near_kept = 2;
  whole.prediction = 40;
  for (int w : {2, 4}) {
    LooFit& m = t.model.set(w);
    m.ok = true;
    m.scale = 0.6;
    m.gain = 2.0;
    m.near_kept = 2;
    m.prediction = 0.5;
  }
  for (int d : {0, 1}) {
    LooFit& line = t.model.set(kWindows + d);
    line.ok = true;
    line.scale = 0.7;
    line.gain = 1.1;
    line.near_kept = 4;
    line.prediction = -0.5;
  }
  return t;
}

}  // namespace

TEST(LtsJudges, APointTwoWindowsAndTwoLinesOfItsSurfaceVouchForIsOutvoted) {
  CHECK(outvoted(envelope_against_its_surface(), 1.0, 5.0));
}

TEST(LtsJudges, OneWindowOrOneStraightLineDoesNotOutvote) {
  PointTest t = envelope_against_its_surface();
  t.model.set(4).scale = 3.0;  // this half-plane straddles a crease: it describes nothing
  CHECK_FALSE(outvoted(t, 1.0, 5.0));
  t = envelope_against_its_surface();
  t.model.set(kWindows + 1).curved = true;  // a curved line extrapolates its curvature: not counted
  CHECK_FALSE(outvoted(t, 1.0, 5.0));
  t = envelope_against_its_surface();
  t.model.set(kWindows + 1).prediction = 30;  // a line that puts it far off does not vouch
  CHECK_FALSE(outvoted(t, 1.0, 5.0));
}

namespace {

// An outlier 33 sigma high on a plate strip one point wide at the scan's edge (the dome at 0.5 um,
// seed 6, (0, 19)): the whole window does not describe its points, a half-plane reaching across
// the rim (gain 3.7) vouches for it, and the straight line along the strip and a quadratic along a
// diagonal put it 4.8 and 2.9 times beyond their bounds.
PointTest vouched_from_across_the_rim() {
  PointTest t;
  t.z = 33;
  t.model.set(0) = fitted(1, 2.6, 1.0, 3);
  LooFit& half = t.model.set(5);
  half.ok = true;
  half.scale = 1.6;
  half.gain = 3.7;
  half.near_kept = 2;
  half.prediction = 29;  // bound 5 sqrt(4.7 + 1.6^2) = 13.5
  LooFit& straight = t.model.set(kWindows + 3);
  straight.ok = true;
  straight.gain = 1.1;
  straight.near_kept = 4;
  straight.prediction = 5;  // 28 off, bound 0.8 x 5 sqrt(2.1) = 5.8
  LooFit& quadratic = t.model.set(kWindows + 2);
  quadratic.ok = true;
  quadratic.curved = true;
  quadratic.scale = 0.76;
  quadratic.gain = 4.6;
  quadratic.near_kept = 4;
  quadratic.prediction = 6;  // 27 off, bound 0.8 x 5 sqrt(5.6) = 9.5
  return t;
}

}  // namespace

TEST(LtsJudges, APointOnlyAWindowReachingFromAfarVouchesForIsVouchedOnlyFromAfar) {
  PointTest t = vouched_from_across_the_rim();
  CHECK(vouches(t, 5, 1.0, 5.0, true));
  CHECK(vouched_only_from_afar(t, 1.0, 5.0));
  // Not where a vouching window reaches it from nearer (gain 3 or less).
  t.model.set(5).gain = 2.5;
  CHECK(vouches(t, 5, 1.0, 5.0, true));
  CHECK_FALSE(vouched_only_from_afar(t, 1.0, 5.0));
  // Nor where no window vouches at all: the judges condemned it or had none.
  t.model.set(5).gain = 3.7;
  t.model.set(5).prediction = 10;
  CHECK_FALSE(vouched_only_from_afar(t, 1.0, 5.0));
}

TEST(LtsJudges, TwoLinesThatDescribeTheirPointsFarFromThePointStandAgainstIt) {
  PointTest t = vouched_from_across_the_rim();
  CHECK(lines_stand_against(t, 1.0, 5.0));
  // One line alone does not: the quadratic within twice its bound (27 -> 17 off, 1.8 bounds).
  t.model.set(kWindows + 2).prediction = 16;
  CHECK_FALSE(lines_stand_against(t, 1.0, 5.0));
  // Nor two where a third line that describes its points predicts the point.
  t = vouched_from_across_the_rim();
  LooFit& third = t.model.set(kWindows + 6);
  third.ok = true;
  third.gain = 1.1;
  third.near_kept = 4;
  third.prediction = 31;
  CHECK_FALSE(lines_stand_against(t, 1.0, 5.0));
  // A line that does not describe its points (a crease along it) is no evidence either way.
  third.scale = 3.0;
  CHECK(lines_stand_against(t, 1.0, 5.0));
}

TEST(LtsJudges, TwoNearWindowsThatPutThePointBeyondTheirBoundsStandAgainstIt) {
  // The ball plate's outlier at 2 um (seed 4, (15, 12)): half-planes of gain 2.0 and 0.85 put it
  // 2.1 and 1.4 times beyond their bounds.
  PointTest t;
  t.z = -27;
  for (int w : {5, 8}) {
    LooFit& m = t.model.set(w);
    m.ok = true;
    m.near_kept = 3;
  }
  t.model.set(5).scale = 1.8;
  t.model.set(5).gain = 1.96;  // bound 5 sqrt(2.96 + 1.8^2) = 12.4
  t.model.set(8).scale = 1.1;
  t.model.set(8).gain = 0.85;  // bound 5 sqrt(1.85 + 1.1^2) = 8.7
  t.model.set(8).prediction = -14.5;
  CHECK(windows_stand_against(t, 1.0, 5.0));
  // Not with one of them within its bound.
  t.model.set(8).prediction = -20;
  CHECK_FALSE(windows_stand_against(t, 1.0, 5.0));
  t.model.set(8).prediction = -14.5;
  // Nor where one predicts from farther (gain over 2), keeps two nearest neighbours only, or does
  // not describe its points.
  t.model.set(5).gain = 2.5;
  CHECK_FALSE(windows_stand_against(t, 1.0, 5.0));
  t.model.set(5).gain = 1.96;
  t.model.set(5).near_kept = 2;
  CHECK_FALSE(windows_stand_against(t, 1.0, 5.0));
  t.model.set(5).near_kept = 3;
  t.model.set(5).scale = 2.2;
  CHECK_FALSE(windows_stand_against(t, 1.0, 5.0));
}

namespace {

// The sphere's outlier at 5 um (seed 8, (10, 13)): the whole window (2.6 sigma) puts it 11.5 sigma
// off, 0.8 of its bound, and a half-plane describing its points 1.6 times beyond its own.
PointTest leaned_against() {
  PointTest t;
  t.z = 11.5;
  t.model.set(0) = fitted(0, 2.6, 0.4, 3);      // bound 5 hypot(1, 2.6) = 13.9
  t.model.set(5) = fitted(-4.9, 1.08, 2.0, 3);  // 16.4 off, bound 5 sqrt(3 + 1.08^2) = 10.2
  return t;
}

using Change = std::function<void(PointTest&)>;

// Checks that `holds` gives `expected` on `made()` after each one of `changes`.
void check_each_change(PointTest (*made)(), std::initializer_list<Change> changes,
                       const std::function<bool(const PointTest&)>& holds, bool expected) {
  for (const Change& change : changes) {
    PointTest t = made();
    change(t);
    CHECK_EQUAL(expected, holds(t));
  }
}

}  // namespace

TEST(LtsJudges, WindowsOnItsSurfaceLeanAgainstAPointTheWholeWindowPutsOverHalfItsBoundOff) {
  CHECK(windows_lean_against(leaned_against(), 1.0, 5.0));
  check_each_change(leaned_against,
                    {
                        [](PointTest& t) { t.model.set(0).prediction = 5; },  // the whole window within half its bound
                        [](PointTest& t) { t.model.set(0).scale = 3.2; },     // nor following the surface to 3 sigma
                        [](PointTest& t) { t.model.set(5).prediction = 2; },  // the half-plane within its bound
                        [](PointTest& t) { t.model.set(5).near_kept = 2; },   // or keeping two nearest neighbours only
                    },
                    [](const PointTest& t) { return windows_lean_against(t, 1.0, 5.0); }, false);
}

namespace {

// A point at the origin and one side of its line along -x: eight points on z = 0.5 t^2 (sigma 1),
// the point on that curve too.
struct OneSidedLine {
  std::vector<dg::host::Point3> points;
  LineSides sides;
  std::vector<char> suspect;
  OneSidedLine() {
    points.push_back({0, 0, 0});
    for (int t = 1; t <= 8; ++t) {
      points.push_back({-static_cast<double>(t), 0, 0.5 * t * t});
      sides[1].push_back(static_cast<size_t>(t));
    }
    suspect.assign(points.size(), 0);
  }
  PointTest test() const {
    PointTest t;
    t.z = points[0].z;
    add_line_models(points, sides, 0, suspect, 1.0, t);
    return t;
  }
};

}  // namespace

TEST(LtsJudges, ALineThatPredictsItsNearestPointOneStepBackVouchesAlone) {
  const OneSidedLine line;
  const PointTest t = line.test();
  CHECK(vouches(t, kWindows + 1, 1.0, 5.0, true));
  CHECK_FALSE(vouched_only_by_untested_lines(line.points, line.sides, line.suspect, t, 1.0, 5.0));
}

TEST(LtsJudges, ALineThatCannotBeFittedOneStepBackIsUntested) {
  // With the second and third points suspected, the line still predicts the point from the first
  // and the fourth to seventh (gain 2.7), but one step back its nearest point only from the fourth
  // to eighth, three to seven steps away: a gain of 40, beyond kLineGainMax.
  OneSidedLine line;
  line.suspect[2] = line.suspect[3] = 1;
  PointTest t = line.test();
  CHECK(vouches(t, kWindows + 1, 1.0, 5.0, true));
  CHECK(vouched_only_by_untested_lines(line.points, line.sides, line.suspect, t, 1.0, 5.0));
  // Where a window vouches, the lines are not asked.
  t.model.set(0).ok = true;
  t.model.set(0).scale = 1;
  t.model.set(0).gain = 0.5;
  t.model.set(0).near_kept = 4;
  t.model.set(0).prediction = t.z;
  CHECK_FALSE(vouched_only_by_untested_lines(line.points, line.sides, line.suspect, t, 1.0, 5.0));
}

TEST(LtsJudges, ALineWhoseFartherPointsMissItsNearestOneStepBackIsUntested) {
  // The sixth point 30 sigma off the curve: the line through the nearest five still predicts the
  // point exactly, but one step back the second to sixth put the nearest 18 sigma off (the sixth's
  // weight in a quadratic's prediction one step beyond five points is 0.6), beyond the bound of
  // 0.8 x 5 sqrt(1 + 4.6) = 9.5.
  OneSidedLine line;
  line.points[6].z += 30;
  const PointTest t = line.test();
  CHECK(vouches(t, kWindows + 1, 1.0, 5.0, true));
  CHECK(vouched_only_by_untested_lines(line.points, line.sides, line.suspect, t, 1.0, 5.0));
  // 10 sigma off, the nearest is predicted 6 sigma off, within the bound: the line is tested.
  line.points[6].z -= 20;
  CHECK_FALSE(vouched_only_by_untested_lines(line.points, line.sides, line.suspect, line.test(), 1.0, 5.0));
}

namespace {

// The canister's outlier at 0.5 um (seed 1, (16, 12)) beside a pair of outliers: the whole window
// (scale 0.13 sigma, two nearest neighbours kept) puts it 25 sigma low, four times its bound; a
// half-plane of scale 2.03 sigma puts it 2 sigma off but misses a nearest neighbour by 18.
PointTest beside_a_pair() {
  PointTest t;
  t.z = -25.3;
  t.model.set(0) = fitted(0, 0.13, 0.5, 2, 1.8);         // bound 5 hypot(1, 0.13) = 5.0
  t.model.set(8) = fitted(-27.25, 2.03, 1.43, 3, 18.1);  // 1.95 off, bound 5 sqrt(2.43 + 2.03^2) = 12.8
  return t;
}

}  // namespace

TEST(LtsJudges, AHalfPlaneMissingANearestNeighbourDoesNotNearlyVouchFarOffATightWholeWindow) {
  CHECK_FALSE(whole_overrules(beside_a_pair(), 1.0, 5.0));  // it keeps two nearest neighbours only
  CHECK_FALSE(a_half_plane_nearly_vouches(beside_a_pair(), 1.0, 5.0));
  // The half-plane still nearly vouches where it predicts the nearest neighbours within its bound,
  // where the whole window does not describe its points, or puts the point within twice its bound.
  check_each_change(beside_a_pair,
                    {
                        [](PointTest& t) { t.model.set(8).near_worst = 10; },
                        [](PointTest& t) { t.model.set(0).scale = 2.2; },
                        [](PointTest& t) { t.model.set(0).prediction = -16; },
                    },
                    [](const PointTest& t) { return a_half_plane_nearly_vouches(t, 1.0, 5.0); }, true);
}

namespace {

// The dome's pair on its rim at 0.5 um (seed 12, (37, 14)): the whole window (scale 0.46 sigma,
// two nearest neighbours kept, the other being the pair's) puts the point 207 sigma high; a
// half-plane holding the pair's other point puts it 1.7 sigma off and misses that nearest neighbour
// by 210 sigma, 22 times its bound.
PointTest beside_its_pair_on_the_rim() {
  PointTest t;
  t.z = 207;
  t.model.set(0) = fitted(0, 0.46, 0.43, 2, 210);           // bound 5 hypot(1, 0.46) = 5.5
  t.model.set(2) = fitted(208.71, 1.08, 1.56, 3, 210.4);  // bound 5 sqrt(2.56 + 1.08^2) = 9.7
  return t;
}

}  // namespace

TEST(LtsJudges, AHalfPlaneHoldingTheOutlierBesideThePointDoesNotVouchFarOffATightWholeWindow) {
  CHECK_FALSE(whole_overrules(beside_its_pair_on_the_rim(), 1.0, 5.0));  // two nearest neighbours kept
  CHECK_FALSE(vouches(beside_its_pair_on_the_rim(), 2, 1.0, 5.0, /*final_judgement=*/true));
  // Not while the suspects are sorted out; nor where the half-plane misses no nearest neighbour far,
  // the whole window does not describe its points, or puts the point within twice its bound.
  CHECK(vouches(beside_its_pair_on_the_rim(), 2, 1.0, 5.0, /*final_judgement=*/false));
  check_each_change(beside_its_pair_on_the_rim,
                    {
                        [](PointTest& t) { t.model.set(2).near_worst = 50; },
                        [](PointTest& t) { t.model.set(0).scale = 2.2; },
                        [](PointTest& t) { t.model.set(0).prediction = 200; },
                    },
                    [](const PointTest& t) { return vouches(t, 2, 1.0, 5.0, /*final_judgement=*/true); }, true);
}

namespace {

// The ball plate's outlier at its foot at 5 um (seed 8, (10, 13)): the whole window, fitted in its
// tangent plane, follows the flank to 3.4 sigma (no description of its points) and puts it 45 sigma
// off; a half-plane describing its points 86 sigma, and a straight line along the plate 152 sigma.
// Nothing vouches for it.
PointTest vouched_for_by_nothing() {
  PointTest t;
  t.z = 45.5;
  t.model.set(0) = fitted(0, 3.42, 0.57, 2, 114);
  t.model.set(8) = fitted(132, 0.91, 1.96, 4, 1.43);
  t.model.set(kWindows + 4) = fitted(-106.8, 0.49, 0.89, 4);
  return t;
}

}  // namespace

TEST(LtsJudges, APointNoModelVouchesForWhileOneDescribesItsPointsIsUnvouched) {
  CHECK(unvouched(vouched_for_by_nothing(), 1.0, 5.0));
  // Not where one model vouches, a window or a line; nor where no model describes its points.
  check_each_change(vouched_for_by_nothing,
                    {
                        [](PointTest& t) { t.model.set(8).prediction = 40; },
                        [](PointTest& t) { t.model.set(kWindows + 4).prediction = 44; },
                        [](PointTest& t) {
                          t.model.set(8).scale = 2.5;
                          t.model.set(kWindows + 4).scale = 2.5;
                        },
                    },
                    [](const PointTest& t) { return unvouched(t, 1.0, 5.0); }, false);
}
