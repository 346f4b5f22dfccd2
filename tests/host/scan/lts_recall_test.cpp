// The LTS filter against outliers the test plants on the simulated parts' true shapes (20 to 250
// sigma at a 5 % rate, and pairs and triples in one window): every one found on the smooth parts,
// nearly every one across the dome's rim, with few false alarms.
#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <random>
#include <set>
#include <tuple>
#include <utility>

#include "host/scan/lts_filter.h"
#include "tests/support/planted_outliers.h"

using namespace dg::host;

namespace {

struct Score {
  double worst_recall = 1, worst_precision = 1;
};

Score score(dg::sim::PartKind kind) {
  Score out;
  for (double sigma_um : {2.0, 5.0}) {
    for (unsigned seed = 1; seed <= 3; ++seed) {
      const dg::test::Planted p = dg::test::plant_outliers(kind, sigma_um, seed);
      const LtsResult r = lts_filter(p.points, LtsOptions{});
      size_t hits = 0;
      for (const LtsOutlier& o : r.outliers) hits += p.outliers.count(o.index);
      const double recall = static_cast<double>(hits) / static_cast<double>(p.outliers.size());
      const double precision = r.outliers.empty() ? 1.0 : static_cast<double>(hits) / static_cast<double>(r.outliers.size());
      out.worst_recall = std::fmin(out.worst_recall, recall);
      out.worst_precision = std::fmin(out.worst_precision, precision);
    }
  }
  std::printf("\n  LTS on the %s at 2 and 5 um, three seeds: worst recall %.3f, worst precision %.3f",
              dg::sim::part_name(kind), out.worst_recall, out.worst_precision);
  return out;
}

// The true part's largest slope from q to a grid neighbour at 1 mm (mm per mm).
double steepest_slope(dg::sim::PartKind kind, const dg::host::Point3& q) {
  double steepest = 0;
  for (int dx = -1; dx <= 1; ++dx) {
    for (int dy = -1; dy <= 1; ++dy) {
      if (dx == 0 && dy == 0) continue;
      const double rise = dg::sim::shape_height_mm(kind, q.x + dx, q.y + dy) - dg::sim::shape_height_mm(kind, q.x, q.y);
      steepest = std::max(steepest, std::fabs(rise) / std::hypot(dx, dy));
    }
  }
  return steepest;
}

// The points the filter caught or listed as not judged.
std::set<size_t> caught_or_listed(const LtsResult& r) {
  std::set<size_t> seen(r.unjudged.begin(), r.unjudged.end());
  for (const LtsOutlier& o : r.outliers) seen.insert(o.index);
  return seen;
}

// One planted outlier: the scan's noise and seed, and the outlier's point number.
struct PlantedOutlier {
  double sigma_um;
  unsigned seed;
  size_t index;
};

// Each outlier is planted on its scan of `part`, and the filter catches it or lists it.
void check_caught_or_listed(dg::sim::PartKind part, std::initializer_list<PlantedOutlier> outliers) {
  for (const PlantedOutlier& o : outliers) {
    const dg::test::Planted p = dg::test::plant_outliers(part, o.sigma_um, o.seed);
    CHECK(p.outliers.count(o.index) == 1);
    const LtsResult r = lts_filter(p.points, LtsOptions{});
    CHECK(caught_or_listed(r).count(o.index) == 1);
  }
}

// Point (x, y) of a planted scan, 41 x 31 at 1 mm: even lines run forward, odd ones back.
size_t grid_index(const dg::test::Planted& p, int x, int y) {
  const size_t i = static_cast<size_t>(y * 41 + (y % 2 == 0 ? x : 40 - x));
  DOUBLES_EQUAL(x, p.points[i].x, 1e-9);
  DOUBLES_EQUAL(y, p.points[i].y, 1e-9);
  return i;
}

// Whether the filter caught (condemned) point i.
bool caught(const LtsResult& r, size_t i) {
  return std::any_of(r.outliers.begin(), r.outliers.end(), [i](const LtsOutlier& o) { return o.index == i; });
}

// What check_not_condemned asks besides: nothing, that the point is not listed as not judged
// either, or that it is.
enum class Listing { kEither, kNotListed, kListed };

// Each real point (x, y) of the planted scan of `part` at `sigma_um` and `seed` is not condemned,
// and is or is not listed as not judged as `listing` asks.
void check_not_condemned(dg::sim::PartKind part, double sigma_um, unsigned seed,
                         std::initializer_list<std::pair<int, int>> points, Listing listing = Listing::kEither) {
  const dg::test::Planted p = dg::test::plant_outliers(part, sigma_um, seed);
  const LtsResult r = lts_filter(p.points, LtsOptions{});
  for (const std::pair<int, int>& xy : points) {
    const size_t i = grid_index(p, xy.first, xy.second);
    CHECK(p.outliers.count(i) == 0);
    CHECK(!caught(r, i));
    if (listing != Listing::kEither) CHECK(caught_or_listed(r).count(i) == (listing == Listing::kListed ? 1u : 0u));
  }
}

}  // namespace

TEST_GROUP(LtsRecall){};

// Smooth parts, edges and corners of the scan included.
TEST(LtsRecall, FindsEveryOutlierOfTwentySigmaOnSmoothPartsWithFewFalseAlarms) {
  for (dg::sim::PartKind kind : {dg::sim::PartKind::kSaddle, dg::sim::PartKind::kCanister, dg::sim::PartKind::kFlat}) {
    const Score s = score(kind);
    CHECK(s.worst_recall >= 1.0);
    CHECK(s.worst_precision >= 0.95);
  }
}

// The dome's rim is a crease that grazes the scan's edges and corners: there a point on a sliver
// of base plate one grid step wide has no window on its own side; the lines along the scan's rows,
// columns and diagonals, a window cut in two along the rim, and the envelope of the cap's and the
// plate's models vouch for it or condemn it. Measured at 2 and 5 um: recall and precision 1.000
// (before windows condemned only beyond the noise their gain amplifies 0.989 and 0.979; before the
// sliver's lines were asked again 0.989 and 0.959; before the envelope 0.968 and 0.958; before the
// cut 0.957 and 0.957). At 0.5 and 10 um (the benchmark) a few are still missed on slivers one point
// wide along the scan's edges, where no side of any window holds enough plate to model.
TEST(LtsRecall, CatchesEveryOutlierAcrossTheDomesRimAtTwoAndFiveMicrometres) {
  const Score s = score(dg::sim::PartKind::kDome);
  CHECK(s.worst_recall >= 1.0);
  CHECK(s.worst_precision >= 0.95);
}

TEST(LtsRecall, TwoOutliersSideBySideOnTheCapAreCaughtByTheRowThroughThem) {
  // Seed 9 plants two outliers side by side on the cap's steep flank, (21, 7) and (22, 7), 52 and
  // 58 sigma high at 2 um (at 0.5 um only the first): the windows, with both in them, vouched for
  // them. The row through the pair, without them, is the cap's smooth curve on both sides.
  for (double sigma_um : {0.5, 2.0}) {
    const dg::test::Planted p = dg::test::plant_outliers(dg::sim::PartKind::kDome, sigma_um, 9);
    const LtsResult r = lts_filter(p.points, LtsOptions{});
    std::set<size_t> found;
    for (const LtsOutlier& o : r.outliers) found.insert(o.index);
    for (size_t i : {size_t{305}, size_t{306}}) {
      if (!p.outliers.count(i)) continue;
      CHECK(std::fabs(p.points[i].y - 7) < 1e-9);
      CHECK(found.count(i) == 1);
    }
  }
}

TEST(LtsRecall, AnOutlierOnTheBasePlatesSliverAlongTheScansEdgeIsCaught) {
  // At 10 um, seed 2 puts (0, 9) 51 sigma low: on the base plate, which there is a strip one or two
  // points wide between the scan's edge and the cap's rim. The envelope of the cap's and the
  // plate's models, whose plate side holds only a few points there, must judge it.
  const dg::test::Planted p = dg::test::plant_outliers(dg::sim::PartKind::kDome, 10.0, 2);
  const LtsResult r = lts_filter(p.points, LtsOptions{});
  const size_t planted = 409;
  CHECK(p.outliers.count(planted) == 1);
  CHECK(std::fabs(p.points[planted].x) < 1e-9 && std::fabs(p.points[planted].y - 9) < 1e-9);
  bool found = false;
  for (const LtsOutlier& o : r.outliers) found = found || o.index == planted;
  CHECK(found);
}

TEST(LtsRecall, APlatePointBesideTheRimIsNotJudgedByTheCapContinuedBelowThePlate) {
  // At 0.5 um, seed 10: (40, 10) is clean, on the base plate's strip between the rim and the scan's
  // edge. Its whole window's cubic, the cap continued below the plate with the plate's points
  // trimmed, put it far off; a window that misses three unsuspected points is no one surface.
  check_not_condemned(dg::sim::PartKind::kDome, 0.5, 10, {{40, 10}});
}

TEST(LtsRecall, AnOutlierAmongOthersOnASmoothPartIsNotClearedByACutsSide) {
  // The canister at 1 um, seed 13: (2, 29), 36 sigma low, beside the scan's last line, with three
  // outliers around it, (1, 29), (3, 29) and (2, 28). They spoilt its half-planes, so it passed for
  // a point near a crease, and a side of its window's best cut, fitted beside them, predicted it to
  // 2.7 sigma and cleared it. Its window without them is one smooth surface and puts it 35 sigma off.
  const dg::test::Planted p = dg::test::plant_outliers(dg::sim::PartKind::kCanister, 1.0, 13);
  const size_t i = grid_index(p, 2, 29);
  CHECK(p.outliers.count(i) == 1);
  for (const auto& xy : {std::pair<int, int>{1, 29}, {3, 29}, {2, 28}}) {
    CHECK(p.outliers.count(grid_index(p, xy.first, xy.second)) == 1);
  }
  CHECK(caught(lts_filter(p.points, LtsOptions{}), i));
}

TEST(LtsRecall, AStepGaugesStepsAndOutliersDoNotPassForItsNoise) {
  // Rows along x cross a 2 mm step every 6 mm, so most of their fifth differences span one, and
  // the planted outliers spoil a quarter of the rest: started from their median, the noise came
  // out at 53.5 um for 5 um (and 65 um for 10), and outliers up to 50 sigma passed.
  for (double sigma_um : {2.0, 5.0, 10.0}) {
    const dg::test::Planted p = dg::test::plant_outliers(dg::sim::PartKind::kStepGauge, sigma_um, 1);
    const LtsResult r = lts_filter(p.points, LtsOptions{});
    CHECK(r.gridded);
    DOUBLES_EQUAL(sigma_um, r.sigma_mm * 1e3, 0.15 * sigma_um);
    size_t hits = 0;
    for (const LtsOutlier& o : r.outliers) hits += p.outliers.count(o.index);
    CHECK(hits + 2 >= p.outliers.size());
  }
}

TEST(LtsRecall, RealPointsAtASpheresFootAreKeptAndListedAsNotJudged) {
  // The reference sphere's flank falls 6 mm in its last grid step to the base: a 1 mm grid does not
  // resolve it, and the judges condemned a ring of its real points (60 of this clean scan), each
  // with a half-plane whose quadratic had put the plate and the ring's neighbours on one curve.
  // Where no model of a point's neighbours describes them, it is kept and listed instead, and every
  // point so listed lies on that flank. With only that, 25 stayed condemned: half-planes whose
  // trimmed quadratic kept three rows, lines across the flank, and points of the slope itself.
  dg::test::PartScan s;
  s.kind = dg::sim::PartKind::kSphere;
  s.sigma_um = 2;
  const dg::host::PointCloud scan = dg::test::scan_part(s, 1);
  const LtsResult r = lts_filter(scan.points, LtsOptions{});
  CHECK(r.gridded);
  CHECK(!r.unjudged.empty());
  for (size_t i : r.unjudged) {
    const dg::host::Point3& p = scan.points[i];
    double steepest_mm = 0;  // the true part's largest rise to a grid neighbour
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        const double rise = dg::sim::shape_height_mm(s.kind, p.x + dx, p.y + dy) - dg::sim::shape_height_mm(s.kind, p.x, p.y);
        steepest_mm = std::max(steepest_mm, std::fabs(rise));
      }
    }
    CHECK(steepest_mm > 1.0);
  }
  CHECK(r.outliers.size() <= 12);
}

TEST(LtsRecall, NoOutlierOnAFlankTheGridDoesNotResolvePassesUnlisted) {
  // On the sphere's flank, where the part slopes over 2 to a grid neighbour, outliers were kept
  // as inliers when the judges did not condemn them (162 over six seeds and five noise levels):
  // their windows cannot tell them from the part's shape, which is what the list of points not
  // judged says. Every point there that no model of its neighbours describes is now listed,
  // condemned or not, so an outlier on the flank is either caught or listed; and so is a point
  // passed because none of its windows describes its neighbours (seed 2's (12, 8), 0.4 mm high,
  // whose whole window missed them by 4.9 sigma). Over those 30 scans none passes where the flank
  // is steeper than 2; 23 still do where it is 0.1 to 2.
  for (unsigned seed : {1u, 2u}) {
    const dg::test::Planted p = dg::test::plant_outliers(dg::sim::PartKind::kSphere, 2.0, seed);
    const LtsResult r = lts_filter(p.points, LtsOptions{});
    const std::set<size_t> seen = caught_or_listed(r);
    size_t on_flank = 0, unseen = 0;
    for (size_t i : p.outliers) {
      const dg::host::Point3& q = p.points[i];
      const double steepest = steepest_slope(dg::sim::PartKind::kSphere, q);
      if (steepest <= 2.0) continue;
      ++on_flank;
      unseen += seen.count(i) == 0;
    }
    CHECK(on_flank >= 5);
    UNSIGNED_LONGS_EQUAL(0, unseen);
  }
}

TEST(LtsRecall, AnOutlierTheModelResolvingItsSurfaceMissesIsListedNotPassed) {
  // A point no judge condemned was kept as an inlier whenever some model of its neighbours showed
  // that the grid resolves the surface there, even when that model put the point far off: on the
  // sphere's flank the window's cubic or a line from one side, 48 to 206 sigma from the point; at a
  // corner of the step gauge's block a level line of the lower block beside it, 1.8 mm below an
  // outlier 167 sigma low. Each scan here passed one or two outliers of 43 to 193 sigma unlisted;
  // now each outlier is caught or listed.
  struct Scan {
    dg::sim::PartKind part;
    unsigned seed;
  };
  for (const Scan& scan : {Scan{dg::sim::PartKind::kSphere, 5}, Scan{dg::sim::PartKind::kSphere, 6},
                           Scan{dg::sim::PartKind::kStepGauge, 5}, Scan{dg::sim::PartKind::kBallPlate, 2}}) {
    const dg::test::Planted p = dg::test::plant_outliers(scan.part, 1.0, scan.seed);
    const LtsResult r = lts_filter(p.points, LtsOptions{});
    const std::set<size_t> seen = caught_or_listed(r);
    size_t unseen = 0;
    for (size_t i : p.outliers) unseen += seen.count(i) == 0;
    UNSIGNED_LONGS_EQUAL(0, unseen);
  }
}

TEST(LtsRecall, AnOutlierOnASpheresCapIsNotClearedByALinesCurvature) {
  // On the reference sphere's cap, a line's quadratic from one side extrapolated the sphere's
  // curvature to the point and vouched for two outliers, 22 sigma low at 0.5 um (seed 4, (22, 16))
  // and 20 sigma high at 5 um (seed 1, (18, 25)), that the whole window and two half-planes put 15
  // to 25 sigma off; both passed unlisted. Each is now caught or listed.
  check_caught_or_listed(dg::sim::PartKind::kSphere, {{0.5, 4, 678}, {5.0, 1, 1047}});
}

TEST(LtsRecall, AnOutlierThatMatchesTheLevelBesideItIsNotClearedByThatLevel) {
  // At the step gauge's edge (seed 7 at 10 um, (39, 13)) an outlier 1.82 mm low read within 7 um of
  // what the model of the lower level beside it predicted there. The point's window, cut in two, put
  // the point on that level's side, whose model kept one of the point's four nearest neighbours and
  // missed the others by 179 sigma; it cleared the point, which passed unlisted. It is now caught or
  // listed.
  check_caught_or_listed(dg::sim::PartKind::kStepGauge, {{10.0, 7, 534}});
}

TEST(LtsRecall, AnOutlierOneLineClearsAgainstEveryOtherModelIsListed) {
  // On the step gauge at 5 um (seed 7, (9, 14)) and 10 um (seed 13, (7, 15)) an outlier 104 and
  // 150 sigma off, near a level's height above its own, passed unlisted: a judge cleared it where
  // five windows describing their points and five or six straight lines put it 5 to 52 times their
  // bounds off, with one line along the level above vouching. Each is now caught or listed.
  check_caught_or_listed(dg::sim::PartKind::kStepGauge, {{5.0, 7, 583}, {10.0, 13, 648}});
}

TEST(LtsRecall, RealPointsOnASpheresFlankCondemnedOnlyNarrowlyAreNotCondemned) {
  // On the reference sphere's flank at 1 um (seed 13), (19, 6) and (20, 6), 9 mm from its axis,
  // were condemned by windows whose cubics leave micrometres of shape error there, at 1.04 to 1.43
  // times their bounds: two of that scan's five false alarms. They were then listed as not judged;
  // with the windows fitted in their tangent planes (kTiltSlope) they pass, judged.
  check_not_condemned(dg::sim::PartKind::kSphere, 1.0, 13, {{19, 6}, {20, 6}}, Listing::kNotListed);
}

TEST(LtsRecall, AnOutlierAtTheScansEdgeBeyondAnExtrapolatingWindowsBoundIsStillCaught) {
  // On the canister at 0.5 um (seed 14) an outlier at the scan's last line, (23, 30), lies 1.34
  // times beyond its whole window's bound, which the window's extrapolation (gain 5) widens: it is
  // caught, not listed as narrowly condemned.
  const dg::test::Planted p = dg::test::plant_outliers(dg::sim::PartKind::kCanister, 0.5, 14);
  const size_t i = grid_index(p, 23, 30);
  CHECK(p.outliers.count(i) == 1);
  CHECK(caught(lts_filter(p.points, LtsOptions{}), i));
}

TEST(LtsRecall, AWholeWindowThatSkipsThePointsRowDoesNotVouchForIt) {
  // On the step gauge a cubic fitted to 70 % of a 5 x 5 window took the rows on either side of a
  // step one row wide and skipped the point's own row: it put outliers 0.5 and 0.98 mm down that
  // step within a few sigma of its prediction, while missing their clean row neighbours by 194 and
  // 257 sigma, and both passed unlisted. Each is now caught or listed.
  check_caught_or_listed(dg::sim::PartKind::kStepGauge, {{2.0, 3, 238}, {5.0, 1, 527}});
}

TEST(LtsRecall, FewRealPointsAtTheBallPlatesFeetAreCondemned) {
  // The balls rise 0.6 mm in their first grid step from the plate; a line along the plate beside a
  // foot point described its own points and condemned the point (18 to 20 of these clean scans
  // were condemned), now the point is taken for one of the slope, which the grid does not resolve.
  // Then a diagonal line along the plate, or a window of the plate that missed the ball's first
  // ring by 0.2 to 0.5 mm, still vouched for the foot and condemned 9 to 16 (at 2 and 5 um); where
  // the surface falls steeply across a point on every line and its window misses even its
  // nearest neighbours, it is not judged, and a point the crease's envelope predicts is cleared.
  // On such a slope only models of the point's own surface judge it (a half-plane of the plate or
  // an envelope that misses the slope's grid neighbours does not): at most 2, 3 and 6 condemned on
  // these nine scans before, 1, 2 and 4 after (at 2, 5 and 10 um).
  for (double sigma_um : {2.0, 5.0, 10.0}) {
    for (unsigned seed = 1; seed <= 3; ++seed) {
      dg::test::PartScan s;
      s.kind = dg::sim::PartKind::kBallPlate;
      s.sigma_um = sigma_um;
      const LtsResult r = lts_filter(dg::test::scan_part(s, seed).points, LtsOptions{});
      CHECK(r.outliers.size() <= (sigma_um < 10 ? 2u : 4u));
    }
  }
}

TEST(LtsRecall, AFlatReadBelowItsGaugesStepLosesNoPoint) {
  // Noise of 0.3 and 0.5 um on 1 um readings: most read alike, and the scatter of the rest is
  // smaller than the rounding's own q / sqrt(12). Judged by that scatter, every reading a step off
  // was condemned (350 of 1,271 points at 0.5 um, seed 5); judged by the reading step's, none is.
  for (double sigma_um : {0.3, 0.5}) {
    for (unsigned seed = 1; seed <= 6; ++seed) {
      dg::test::PartScan s;
      s.kind = dg::sim::PartKind::kFlat;
      s.sigma_um = sigma_um;
      const LtsResult r = lts_filter(dg::test::scan_part(s, seed).points, LtsOptions{});
      LONGS_EQUAL(0, r.outliers.size());
      CHECK(r.sigma_mm >= 0.001 / std::sqrt(12.0) - 1e-12);
      CHECK(r.sigma_mm <= 1.2 * std::sqrt(sigma_um * sigma_um + 1.0 / 12) * 1e-3);
    }
  }
}

TEST(LtsRecall, PlantedOutliersDoNotRaiseTheNoiseEstimate) {
  // Each outlier spoils the ten fifth differences it is in; those it enters at a light end it
  // raises too little to be cut. With them counted the noise came out 11 to 29 % high on these
  // scans (the sphere's band, steeper than the grid resolves, added its own). The truth is the
  // gauge's noise with its 1 um reading step: sqrt(sigma^2 + step^2 / 12).
  const struct {
    dg::sim::PartKind kind;
    double sigma_um;
    unsigned seed;
  } kScans[] = {{dg::sim::PartKind::kSphere, 0.5, 3}, {dg::sim::PartKind::kSphere, 0.5, 4},
                {dg::sim::PartKind::kSphere, 0.5, 5}, {dg::sim::PartKind::kDome, 10.0, 1},
                {dg::sim::PartKind::kDome, 10.0, 3}};
  for (const auto& s : kScans) {
    const dg::test::Planted p = dg::test::plant_outliers(s.kind, s.sigma_um, s.seed);
    const LtsResult r = lts_filter(p.points, LtsOptions{});
    const double truth_um = std::sqrt(s.sigma_um * s.sigma_um + 1.0 / 12);
    DOUBLES_EQUAL(truth_um, r.sigma_mm * 1e3, 0.1 * truth_um);
  }
}

TEST(LtsRecall, WindowsThatKeepAlternatingEndTheIterationWithTheSameOutliers) {
  // Planted outliers on the canister at 2 um: some dozens of windows keep alternating between
  // trimmed subsets, which ran the iteration to its limit of 50 (three quarters of the filter's time
  // on a 120,701-point scan). It now stops once the moving points stop shrinking, and finds what
  // the full run found.
  const dg::test::Planted p = dg::test::plant_outliers(dg::sim::PartKind::kCanister, 2.0, 1);
  const dg::host::LtsResult r = dg::host::lts_filter(p.points, dg::host::LtsOptions{});
  CHECK(r.iterations <= 10);
  CHECK(!r.converged);
  CHECK(r.alternating > 0);
  size_t hits = 0;
  for (const dg::host::LtsOutlier& o : r.outliers) hits += p.outliers.count(o.index);
  LONGS_EQUAL(p.outliers.size(), hits);
}

// Points of base plate within 1.5 mm outside the dome's rim in the scan's corners, one outlier of
// `sigmas` at a time (raised and lowered in turn) on a 5 um scan.
namespace {
struct PlateOutliers {
  size_t tried = 0, caught = 0, listed = 0, false_alarms = 0;
};
PlateOutliers plate_outliers_beside_the_rim(double sigmas) {
  dg::test::PartScan s;
  s.sigma_um = 5;
  const std::vector<Point3> clean = dg::test::scan_part(s, 2).points;
  PlateOutliers out;
  for (size_t i = 0; i < clean.size(); ++i) {
    const double from_centre = std::hypot(clean[i].x - 20, clean[i].y - 15);
    const bool corner = (clean[i].x < 8 || clean[i].x > 32) && (clean[i].y < 6 || clean[i].y > 24);
    if (!corner || from_centre < 20.4 || from_centre > 21.9) continue;
    std::vector<Point3> points = clean;
    points[i].z += (out.tried % 2 ? -sigmas : sigmas) * s.sigma_um * 1e-3;
    ++out.tried;
    const LtsResult r = lts_filter(points, LtsOptions{});
    for (const LtsOutlier& o : r.outliers) (o.index == i ? out.caught : out.false_alarms) += 1;
    out.listed += static_cast<size_t>(std::count(r.unjudged.begin(), r.unjudged.end(), i));
  }
  std::printf("\n  %zu of %zu caught at %g sigma, %zu false alarms", out.caught, out.tried, sigmas, out.false_alarms);
  return out;
}
}  // namespace

// At 100 sigma their 5 x 5 windows are mostly cap, and the rim points beside the outlier had no
// window that describes their neighbours either. Every outlier was caught before the window cut
// along the rim, but with 48 false alarms over the 44 scans; the cut cleared them (2 left), the
// envelope of cap and plate the rest.
TEST(LtsRecall, AnOutlierOnAPlateSliverIsCaughtWithoutCondemningTheRimBesideIt) {
  const PlateOutliers p = plate_outliers_beside_the_rim(100);
  CHECK(p.tried > 40);
  LONGS_EQUAL(p.tried, p.caught);
  CHECK(p.false_alarms <= p.tried / 8);
}

// At 40 sigma (0.2 mm), a point 0.2 mm outside the rim raised by that much reads as the cap's
// continuation to every model of one surface: six were missed with or without the cut. The
// envelope of the cap's and the plate's models (the larger of the two) knows where the cap ends.
// Four of the 44 ((36, 2), (2, 5), (2, 25), (3, 27)) are listed as not judged instead: the whole
// window's cubic, fitted in its tangent plane on the cap's steep edge, follows the cap's
// continuation to 2.5 to 5 sigma and puts the raised point within its own bound, and a point so
// predicted is not known to be off the surface (the resolution judgement in lts_filter.cpp).
TEST(LtsRecall, AFortySigmaOutlierJustOutsideTheRimIsCaughtByTheEnvelopeOfCapAndPlate) {
  const PlateOutliers p = plate_outliers_beside_the_rim(40);
  CHECK(p.tried > 40);
  CHECK(p.caught + p.listed == p.tried);
  CHECK(p.caught * 10 >= p.tried * 9);
  CHECK(p.false_alarms <= p.tried / 8);
}

// Two outliers side by side on a smooth part (the canister at 0.5 um, 24 and -135 sigma): each
// spoilt the other's whole window, which then could not judge, and a line along the row, whose
// extrapolation errs by several sigma on the dish, vouched for the smaller one. The whole window
// now passes over a neighbour that is itself suspected.
TEST(LtsRecall, TwoOutliersSideBySideOnASmoothPartAreBothCaught) {
  dg::test::PartScan s;
  s.kind = dg::sim::PartKind::kCanister;
  s.sigma_um = 0.5;
  std::vector<Point3> points = dg::test::scan_part(s, 3).points;
  size_t first = points.size(), second = points.size();
  for (size_t i = 0; i < points.size(); ++i) {
    if (points[i].x == 28 && points[i].y == 24) first = i;
    if (points[i].x == 29 && points[i].y == 24) second = i;
  }
  CHECK(first < points.size() && second < points.size());
  points[first].z += 24 * s.sigma_um * 1e-3;
  points[second].z -= 135 * s.sigma_um * 1e-3;
  const LtsResult r = lts_filter(points, LtsOptions{});
  std::set<size_t> found;
  for (const LtsOutlier& o : r.outliers) found.insert(o.index);
  CHECK(found.count(first) == 1);
  CHECK(found.count(second) == 1);
  CHECK(found.size() <= 3);
}

// The base plate between the dome's rim and the scan's edge at x = 40 is one point wide from y = 8
// to 10. An outlier on it at (40, 8) is caught only by the envelope of cap and plate, after the
// windows have judged; the lines along the edge had read it as a plate point, so none vouched for
// (40, 9) beside it, and the half-planes, all cap, condemned it 0.44 mm off (and then (40, 10)).
// The lines are now asked again without the envelope's outliers, and fall back to a straight line
// where the plate's curvature is noise. Before: 8 of the 12 scans condemned a sliver point.
TEST(LtsRecall, AnOutlierOnAOnePointSliverDoesNotTakeTheSliverPointsBesideItWithIt) {
  dg::test::PartScan s;
  s.sigma_um = 0.5;
  int caught = 0, false_alarms = 0;
  for (unsigned seed = 1; seed <= 6; ++seed) {
    for (double sigmas : {40.0, 85.0}) {
      std::vector<Point3> points = dg::test::scan_part(s, seed).points;
      size_t outlier = points.size();
      for (size_t i = 0; i < points.size(); ++i) {
        if (points[i].x == 40 && points[i].y == 8) outlier = i;
      }
      CHECK(outlier < points.size());
      points[outlier].z += sigmas * s.sigma_um * 1e-3;
      const LtsResult r = lts_filter(points, LtsOptions{});
      for (const LtsOutlier& o : r.outliers) {
        if (o.index == outlier) {
          ++caught;
        } else if (points[o.index].x == 40 && points[o.index].y >= 9 && points[o.index].y <= 10) {
          ++false_alarms;
        }
      }
    }
  }
  std::printf("\n  %d of 12 sliver outliers caught, %d sliver points beside them condemned", caught, false_alarms);
  LONGS_EQUAL(12, caught);
  LONGS_EQUAL(0, false_alarms);
}

// Seed 12's dome at 0.5 um has an outlier of -137 sigma at (0, 23) and (2, 7) of seed 10 one of
// -51 sigma, each on the rim with other outliers in its window that only the envelope of cap and
// plate condemned. Judged while those still stood in the windows, they were missed; the crease's
// judges now look again, with every condemned point left out, at the points beside a crease that
// they passed (only to condemn; the lines may clear again after).
TEST(LtsRecall, AnOutlierOnTheRimIsJudgedAgainWithTheOutliersTheEnvelopeFoundLeftOut) {
  for (const auto& [seed, x, y] : {std::tuple<unsigned, double, double>{12, 0, 23}, {10, 2, 7}}) {
    const dg::test::Planted p = dg::test::plant_outliers(dg::sim::PartKind::kDome, 0.5, seed);
    size_t planted = p.points.size();
    for (size_t i : p.outliers) {
      if (p.points[i].x == x && p.points[i].y == y) planted = i;
    }
    CHECK(planted < p.points.size());
    const LtsResult r = lts_filter(p.points, LtsOptions{});
    size_t found = 0;
    for (const LtsOutlier& o : r.outliers) found += o.index == planted;
    LONGS_EQUAL(1, found);
  }
}

namespace {

// The planted point at (x, y) of `part` at `sigma_um`, seed `seed`, and whether the filter reports
// it as an outlier.
struct Verdict {
  bool planted = false;
  bool reported = false;
};
Verdict verdict_at(dg::sim::PartKind part, double sigma_um, unsigned seed, double x, double y) {
  const dg::test::Planted p = dg::test::plant_outliers(part, sigma_um, seed);
  size_t at = p.points.size();
  for (size_t i = 0; i < p.points.size(); ++i) {
    if (p.points[i].x == x && p.points[i].y == y) at = i;
  }
  CHECK(at < p.points.size());
  Verdict v;
  v.planted = p.outliers.count(at) == 1;
  for (const LtsOutlier& o : lts_filter(p.points, LtsOptions{}).outliers) v.reported = v.reported || o.index == at;
  return v;
}

}  // namespace

// Seed 6 plants a 2 x 2 block of outliers on the dome's base plate near a corner ((3, 2) to (4, 3),
// 54 to 185 sigma at 0.5 um). The filtered reference had taken the block in, so the trimmed fits
// started from subsets that held it and settled there (a whole window's scale 90 sigma); and the
// rounds that test the points beside suspects without them alternated, each outlier clearing
// another in turn. Two of the four were missed. A second start from the heights nearest the
// window's median, and suspects that stay left out once their whole window condemned them, catch
// the block.
TEST(LtsRecall, ABlockOfFourOutliersNearACornerIsCaughtWhole) {
  for (const auto& [x, y] : {std::pair<double, double>{3, 2}, {4, 2}, {3, 3}, {4, 3}}) {
    const Verdict v = verdict_at(dg::sim::PartKind::kDome, 0.5, 6, x, y);
    CHECK(v.planted);
    CHECK(v.reported);
  }
}

// A window's prediction at a corner of the scan is an extrapolation: a whole window's cubic there
// has a gain of 9 to 11, a diagonal half-plane's quadratic up to 39, and clean corner points were
// condemned 5.7 to 10 sigma off (the saddle's (0, 0) of seed 4 and (40, 30) of seed 5 at 1 um, the
// canister's (0, 0) of seed 4 at 0.5 um). A window now condemns a point only beyond the noise its
// own gain amplifies.
TEST(LtsRecall, CleanCornerPointsAreNotCondemnedByAnExtrapolatingWindow) {
  const Verdict saddle_first = verdict_at(dg::sim::PartKind::kSaddle, 1.0, 4, 0, 0);
  const Verdict saddle_last = verdict_at(dg::sim::PartKind::kSaddle, 1.0, 5, 40, 30);
  const Verdict canister = verdict_at(dg::sim::PartKind::kCanister, 0.5, 4, 0, 0);
  for (const Verdict& v : {saddle_first, saddle_last, canister}) {
    CHECK(!v.planted);
    CHECK(!v.reported);
  }
}

// With that bound a whole window at the scan's edge, its suspects left out, could no longer resolve
// an outlier of 21 sigma (gain 11: a bound of 17.5 sigma against a residual of 16), where
// half-planes with gains below 1 saw it 21 sigma off. Where the judging window's own bound holds,
// the other windows decide as where no window judges alone: the saddle's (0, 28) of seed 1 at 1 um,
// and the dome's (0, 9) of seed 2 at 5 um, which was missed before either change.
TEST(LtsRecall, AnEdgeOutlierTheWholeWindowCannotResolveIsCaughtByAPreciseHalfPlane) {
  for (const Verdict& v : {verdict_at(dg::sim::PartKind::kSaddle, 1.0, 1, 0, 28), verdict_at(dg::sim::PartKind::kDome, 5.0, 2, 0, 9)}) {
    CHECK(v.planted);
    CHECK(v.reported);
  }
}

// A clean point just inside the dome's rim near a corner of the scan, 0.36 mm above the plate (the
// dome's (4, 3) of seed 3 at 0.5 um): the wider window's cut held it with the plate, whose side
// condemned it and would have put a 0.36 mm dent in the surface. Its own window cut along the rim
// has the cap's side predict it to 1.6 sigma and clears it. Of the canister's edge outlier beside
// another ((12, 1) of seed 2 at 0.5 um), the same cut's side came within 6.4 sigma: inside the
// full bound of 10.4, not within the half bound the own window's cut is held to.
TEST(LtsRecall, ARimPointNearACornerIsClearedByItsOwnWindowsCutAlongTheRim) {
  const Verdict rim = verdict_at(dg::sim::PartKind::kDome, 0.5, 3, 4, 3);
  CHECK(!rim.planted);
  CHECK(!rim.reported);
  const Verdict edge = verdict_at(dg::sim::PartKind::kCanister, 0.5, 2, 12, 1);
  CHECK(edge.planted);
  CHECK(edge.reported);
}

// Two clean rim points near the dome's corner (3, 26) and (4, 27) of seed 4 at 0.5 um, 0.14 and
// 0.36 mm above the plate: the first had an envelope of cap and plate 2.15 sigma in scale that
// predicted it to 6.5 sigma (the envelope then judged only at 2 sigma); the second, judged again
// once the first was cleared, an envelope of gain 9.3 that predicted it to 5.7 sigma (the envelope
// then judged only up to a line's gain). Both were condemned by the plate's half-planes.
TEST(LtsRecall, RimPointsAnEnvelopeOfCapAndPlatePredictsAreNotCondemned) {
  for (const Verdict& v : {verdict_at(dg::sim::PartKind::kDome, 0.5, 4, 3, 26), verdict_at(dg::sim::PartKind::kDome, 0.5, 4, 4, 27)}) {
    CHECK(!v.planted);
    CHECK(!v.reported);
  }
}

// At 10 um one cubic describes a window across the dome's rim within 2.5 sigma, and the envelope
// of cap and plate was not tried there; a plate point 0.53 mm low near the scan's edge ((6, 29) of
// seed 3), where the cap continued past its rim dips that far, passed as the cap's. The envelope
// is tried where the smooth cubic keeps fewer than two of the point's four nearest neighbours.
TEST(LtsRecall, APlateOutlierWhereTheCapWouldDipIsCaughtAtTenMicrometres) {
  const Verdict v = verdict_at(dg::sim::PartKind::kDome, 10.0, 3, 6, 29);
  CHECK(v.planted);
  CHECK(v.reported);
}

// The filter shares its points among the cores; one thread or four find the same heights and the
// same outliers, to the last bit.
TEST(LtsRecall, OneThreadAndFourGiveTheSameResult) {
  const dg::test::Planted p = dg::test::plant_outliers(dg::sim::PartKind::kDome, 2.0, 2);
  setenv("DIGITIZER_THREADS", "1", 1);
  const LtsResult one = lts_filter(p.points, LtsOptions{});
  setenv("DIGITIZER_THREADS", "4", 1);
  const LtsResult four = lts_filter(p.points, LtsOptions{});
  unsetenv("DIGITIZER_THREADS");
  CHECK(one.z == four.z);
  LONGS_EQUAL(one.outliers.size(), four.outliers.size());
  for (size_t k = 0; k < one.outliers.size(); ++k) LONGS_EQUAL(one.outliers[k].index, four.outliers[k].index);
  LONGS_EQUAL(one.iterations, four.iterations);
  CHECK(!one.outliers.empty());
}

TEST(LtsRecall, RealPointsOnASteepFlankThatTheWholeWindowPredictsAreNotCondemned) {
  // The reference sphere's flank beside its foot, scanned at 0.1 mm with readings free of noise but
  // for their 1 um rounding: a 5 x 5 window's cubic follows the surface to 2.5 to 5 noise sigmas
  // there. The filter condemned five real points 12 to 27 sigma off (the one examined, (23.6, 3.1),
  // by a half-plane's quadratic extrapolating with a gain of 4.6, where the whole window's cubic put
  // it 2.4 sigma off). They were then listed as not judged; with the windows fitted in their
  // tangent planes (kTiltSlope) they pass, judged, and the scan has no false alarm left.
  std::vector<Point3> points;
  for (int iy = 0; iy < 50; ++iy) {
    for (int ix = 0; ix < 60; ++ix) {
      const double x = 21 + 0.1 * ix, y = 2 + 0.1 * iy;
      points.push_back({x, y, std::round(dg::sim::shape_height_mm(dg::sim::PartKind::kSphere, x, y) * 1000) / 1000});
    }
  }
  const LtsResult r = lts_filter(points, LtsOptions{});
  CHECK(r.gridded);
  const std::set<size_t> listed(r.unjudged.begin(), r.unjudged.end());
  std::set<size_t> condemned;
  for (const LtsOutlier& o : r.outliers) condemned.insert(o.index);
  for (const auto& [x, y] : {std::pair{23.6, 3.1}, {23.9, 3.2}, {24.2, 3.3}, {24.6, 3.5}, {25.9, 4.1}}) {
    const size_t i = static_cast<size_t>(std::lround((y - 2) / 0.1)) * 60 + static_cast<size_t>(std::lround((x - 21) / 0.1));
    DOUBLES_EQUAL(x, points[i].x, 1e-9);
    CHECK(listed.count(i) == 0);
    CHECK(condemned.count(i) == 0);
  }
  CHECK(r.outliers.empty());
}

TEST(LtsRecall, ARealPointTheWholeWindowPutsWithinItsShapeErrorIsNotCondemned) {
  // The reference sphere at 0.5 um, seed 4: at (21, 6), where it slopes about 1, the whole window's
  // cubic follows the surface to 3.8 sigma and put the real point 6.4 sigma off, just beyond the
  // bound of the noise alone; a half-plane condemned it 14 sigma off. With the window's shape error
  // beyond a describing window's in the bound, it was listed as not judged; with the windows fitted
  // in their tangent planes (kTiltSlope) it passes, judged.
  const dg::test::Planted p = dg::test::plant_outliers(dg::sim::PartKind::kSphere, 0.5, 4);
  const size_t i = 6 * 41 + 21;  // line 6 runs forward
  DOUBLES_EQUAL(21, p.points[i].x, 1e-9);
  DOUBLES_EQUAL(6, p.points[i].y, 1e-9);
  CHECK(p.outliers.count(i) == 0);
  const LtsResult r = lts_filter(p.points, LtsOptions{});
  CHECK(std::find(r.unjudged.begin(), r.unjudged.end(), i) == r.unjudged.end());
  for (const LtsOutlier& o : r.outliers) CHECK(o.index != i);
}

TEST(LtsRecall, ARealPointAtABallsFootThatTheWholeWindowPredictsIsCleared) {
  // The ball plate at 10 um, seed 1: the crease's envelope of plate and ball put the real point
  // (20, 14) on a ball's foot 1.18 mm off, where the whole window's cubic, describing its points,
  // predicted it within the bound of a left-out point's prediction (its gain counted).
  check_not_condemned(dg::sim::PartKind::kBallPlate, 10.0, 1, {{20, 14}});
}

TEST(LtsRecall, APlateBesideABallsFootDoesNotCondemnTheSlopeAboveIt) {
  // The ball plate at 10 um, seed 5: four real points on a ball's flank beside its foot, where the
  // ball rises 0.6 to 1.2 mm a grid step, lie between their neighbours on every line. A half-plane
  // of the plate, describing its own points to the noise, put (19, 12), (17, 10) and (10, 14) 0.5
  // to 1.3 mm off; the envelope of plate and quadratic cap, which trimmed the foot's few points,
  // put (20, 17) 15 sigma off. Each condemned its point. They are models of another surface than
  // the slope's: the points are kept (listed as not judged where no model of theirs judges them).
  check_not_condemned(dg::sim::PartKind::kBallPlate, 10.0, 5, {{19, 12}, {17, 10}, {10, 14}, {20, 17}});
}

TEST(LtsRecall, AnOutlierOnAStepsEdgeBetweenItsTwoLevelsIsStillCaught) {
  // The step gauge, seed 3: (7, 5) on the upper level's edge reads 0.25 mm low, between the level
  // beside it and the one below, and so lies between its neighbours on every line, as a slope point
  // does. Both levels are described to the noise, one above the point and one below: it is no slope
  // point, and the upper level's half-plane still condemns it.
  for (double sigma_um : {0.5, 1.0, 2.0}) {
    const dg::test::Planted p = dg::test::plant_outliers(dg::sim::PartKind::kStepGauge, sigma_um, 3);
    const size_t i = grid_index(p, 7, 5);
    CHECK(p.outliers.count(i) == 1);
    CHECK(caught(lts_filter(p.points, LtsOptions{}), i));
  }
}

TEST(LtsRecall, APlatePointAtABallsFootIsClearedByTheHalfPlaneOfThePlate) {
  // The ball plate at 10 um, seed 4: the four plate points at a ball's foot on its diagonals, where
  // the ball meets the plate. The wide window's envelope of plate and quadratic cap vouched for
  // each first and put it 0.17 to 0.35 mm high (the quadratic is no sphere near the foot), so the
  // points stayed condemned; a diagonal half-plane of the plate, which describes its points and
  // predicts the point's grid neighbours on its side, predicts each within its bound, and clears it.
  check_not_condemned(dg::sim::PartKind::kBallPlate, 10.0, 4, {{11, 11}, {19, 11}, {19, 19}, {11, 19}}, Listing::kNotListed);
}

TEST(LtsRecall, PlatePointsAtABallsFootThatModelsOfThePlateVouchForAreListedNotCondemned) {
  // The ball plate at 10 um, seed 2: the envelope of the plate and a quadratic cap (no sphere at its
  // foot) put (9, 15), (11, 11) and (11, 19) 13 to 31 sigma low, where two or three half-planes
  // of the plate and two to five straight lines along it predicted within their bounds. Three of the
  // scan's six false alarms; they are now listed as not judged.
  check_not_condemned(dg::sim::PartKind::kBallPlate, 10.0, 2, {{9, 15}, {11, 11}, {11, 19}}, Listing::kListed);
}

TEST(LtsRecall, AnOutlierOnAPlateStripThatTheCapContinuedWouldMeetIsListed) {
  // At the scan's edge beside the dome's rim the base plate is a strip one point wide. Outliers
  // there 44 to 84 sigma below it lay near the cap's surface continued past the rim, and the cap's
  // windows vouched for them: (0, 21) at 10 um in seeds 8 and 12, (40, 9) at 5 um in seed 10. The
  // plate's points along the edge, a straight run on both sides of each, put it far below. At the
  // step gauge's edge at 10 um (seed 3, (6, 5)) one 70 sigma low also passed unlisted (its cause was
  // not taken apart). Each is now caught or listed.
  check_caught_or_listed(dg::sim::PartKind::kDome, {{10.0, 8, 901}, {10.0, 12, 901}, {5.0, 10, 369}});
  check_caught_or_listed(dg::sim::PartKind::kStepGauge, {{10.0, 3, 239}});
}

TEST(LtsRecall, AnOutlierThatTheWholeWindowPutsFarOffIsNotClearedByALooseModel) {
  // The sphere, seed 9: (22, 7) on the flank reads about 50 sigma above the true shape, beside two
  // more outliers. At 0.5 um a quadratic along one line, at 2 um a half-plane that missed a nearest
  // neighbour by 224 sigma, vouched for it, while the whole window, describing its points and
  // interpolating, put it more than three times beyond its bound. The whole window overrules them,
  // and it is caught.
  for (double sigma_um : {0.5, 2.0}) {
    const dg::test::Planted p = dg::test::plant_outliers(dg::sim::PartKind::kSphere, sigma_um, 9);
    const size_t i = grid_index(p, 22, 7);
    CHECK(p.outliers.count(i) == 1);
    CHECK(caught(lts_filter(p.points, LtsOptions{}), i));
  }
}


TEST(LtsRecall, AnOutlierOnAPlateStripAtTheScansEdgeVouchedForFromAcrossTheRimIsListed) {
  // The dome at 0.5 um, seed 6: (0, 19) lies on the base plate where it is a strip one point wide
  // along the scan's edge, 33 sigma high. Two half-planes reaching across the rim (gain 3.7)
  // vouched for it; the straight line along the strip and a quadratic along a diagonal put it 28
  // and 27 sigma off. It passed unlisted; now it is at least listed.
  check_caught_or_listed(dg::sim::PartKind::kDome, {{0.5, 6, 819}});
}

TEST(LtsRecall, AnOutlierOnABallsFlankVouchedForFromAfarAgainstTwoNearWindowsIsListed) {
  // The ball plate at 2 um, seed 4: (15, 12) on a ball's flank, 27 sigma low beside another
  // outlier, passed on the word of one half-plane reaching to it from far (gain 8.2), while two
  // half-planes on its side of the ball put it 2.1 and 1.4 times beyond their bounds.
  check_caught_or_listed(dg::sim::PartKind::kBallPlate, {{2.0, 4, 507}});
}

TEST(LtsRecall, AnOutlierOnTheSpheresFlankThatOnlyAnUntestedLineVouchesForIsListed) {
  // The sphere at 5 um, seed 8: (10, 13), 19 sigma above the true shape, passed on the word of one
  // diagonal's quadratic that one step back, without the suspects beside it, could not be fitted
  // within its gain limit, while a half-plane and the whole window leaned against it.
  check_caught_or_listed(dg::sim::PartKind::kSphere, {{5.0, 8, 563}});
}

TEST(LtsRecall, AnOutlierBesideAPairIsCaughtWhereOnlyAHalfPlaneHoldingThePairPredictsIt) {
  // Each 25 to 238 sigma off a whole window that describes the rest (0.13 to 0.57 sigma) but keeps
  // only one or two of its nearest neighbours, beside outliers; a half-plane holding them put it
  // within half its bound, and it was listed as not judged instead of caught.
  const struct {
    dg::sim::PartKind part;
    PlantedOutlier outlier;
  } cases[] = {{dg::sim::PartKind::kCanister, {0.5, 1, 508}}, {dg::sim::PartKind::kCanister, {1.0, 8, 925}},
               {dg::sim::PartKind::kDome, {0.5, 12, 611}}, {dg::sim::PartKind::kDome, {5.0, 12, 536}}};
  for (const auto& c : cases) {
    const dg::test::Planted p = dg::test::plant_outliers(c.part, c.outlier.sigma_um, c.outlier.seed);
    CHECK(p.outliers.count(c.outlier.index) == 1);
    const LtsResult r = lts_filter(p.points, LtsOptions{});
    bool caught = false;
    for (const LtsOutlier& o : r.outliers) caught = caught || o.index == c.outlier.index;
    CHECK(caught);
  }
}

TEST(LtsRecall, OutliersOnTheSpheresFlankAreCaughtByModelsInItsTangentPlane) {
  // Where the reference sphere slopes 1 to 2.5 to a grid neighbour (9 to 11.5 mm from its axis) a
  // window's cubic in x and y leaves tens of micrometres of shape error, and outliers there were
  // listed as not judged instead of caught (6 of the 17 on seeds 1 and 2 at 2 um). Fitted in their
  // tangent planes (kTiltSlope) the windows follow the flank to a few micrometres and catch them.
  size_t on_flank = 0, flank_caught = 0;
  for (unsigned seed : {1u, 2u}) {
    const dg::test::Planted p = dg::test::plant_outliers(dg::sim::PartKind::kSphere, 2.0, seed);
    const LtsResult r = lts_filter(p.points, LtsOptions{});
    for (size_t i : p.outliers) {
      const dg::host::Point3& q = p.points[i];
      const double steepest = steepest_slope(dg::sim::PartKind::kSphere, q);
      if (steepest < 1.0 || steepest > 2.5) continue;
      ++on_flank;
      flank_caught += caught(r, i);
    }
  }
  std::printf("\n  sphere's flank at 2 um, seeds 1 and 2: %zu of %zu outliers caught", flank_caught, on_flank);
  CHECK(on_flank >= 10);
  CHECK(flank_caught >= on_flank - 1);
}

TEST(LtsRecall, ARingPointAboveABallsFootIsNotJudgedByALineClimbingThroughIt) {
  // The ball plate at 5 um, seed 9: (14, 10) and (10, 16) lie on a ball's first ring above its
  // foot, 1.2 mm above the plate a grid step away. The half-planes of the plate condemned
  // them, and a straight line of the plate from one side, a diagonal within 30 degrees of the level
  // direction by the neighbours' rough slope, said the surface was resolved, so they stayed
  // condemned; on the diagonal's other side the ball rises 2 mm. Such a line climbs the slope
  // through the point, and no longer judges it: they are kept, not judged.
  check_not_condemned(dg::sim::PartKind::kBallPlate, 5.0, 9, {{14, 10}, {10, 16}}, Listing::kListed);
}

TEST(LtsRecall, OnTheBallPlateAtFiveMicrometresNineteenInTwentyCondemnedPointsAreOutliers) {
  // Seeds 7 to 14: the worst scan (seed 9) was at 0.948, with five real points on a ball's first
  // ring among those condemned; now three.
  for (unsigned seed = 7; seed <= 14; ++seed) {
    const dg::test::Planted p = dg::test::plant_outliers(dg::sim::PartKind::kBallPlate, 5.0, seed);
    const LtsResult r = lts_filter(p.points, LtsOptions{});
    size_t hits = 0;
    for (const LtsOutlier& o : r.outliers) hits += p.outliers.count(o.index);
    CHECK(!r.outliers.empty());
    CHECK(static_cast<double>(hits) >= 0.95 * static_cast<double>(r.outliers.size()));
  }
}
