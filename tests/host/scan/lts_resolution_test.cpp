// The LTS filter's resolution judges on hand-made lines: what a pit narrower than the grid is.
#include <CppUTest/TestHarness.h>

#include <vector>

#include "host/scan/lts_resolution.h"

using namespace dg::host;
using namespace dg::host::lts;

namespace {

// Point 0 at x = 0 on a row along x; the others at x = 1, 2, ... (side 1, +x) and x = -1, -2, ...
// (side 0, -x), with the heights given. Returns the point's sides, the other lines empty.
struct Row {
  std::vector<Point3> points;
  LineSides sides{};
};

Row row(double z0, const std::vector<double>& plus_x, const std::vector<double>& minus_x) {
  Row r;
  r.points.push_back({0, 0, z0});
  for (size_t m = 0; m < plus_x.size(); ++m) {
    r.sides[1].push_back(r.points.size());
    r.points.push_back({static_cast<double>(m + 1), 0, plus_x[m]});
  }
  for (size_t m = 0; m < minus_x.size(); ++m) {
    r.sides[0].push_back(r.points.size());
    r.points.push_back({-static_cast<double>(m + 1), 0, minus_x[m]});
  }
  return r;
}

constexpr double kSigma = 0.01, kK = 5;

}  // namespace

TEST_GROUP(LtsResolution){};

TEST(LtsResolution, APointFarBelowAStraightRunSpanningItIsInAPit) {
  // A plate one point wide at the scan's edge: three points at 2.0 on one side, one on the other,
  // and the point 0.45 mm (45 sigma) below them.
  const Row r = row(1.55, {2.0, 2.01, 1.995}, {1.998, 2.4});
  const std::vector<char> marked(r.points.size(), 0);
  CHECK(below_a_straight_run(r.points, r.sides, 0, marked, kSigma, kK, kK * kSigma));
  // Seen from the other side the run is no straight line (2.4 is another surface), and from this
  // one it still is: either side may hold the three.
  const Row flipped = row(1.55, {1.998, 2.4}, {2.0, 2.01, 1.995});
  CHECK(below_a_straight_run(flipped.points, flipped.sides, 0, marked, kSigma, kK, kK * kSigma));
}

TEST(LtsResolution, APointAboveAStraightRunOrOnASlopeIsNoPit) {
  const std::vector<char> none(8, 0);
  // Above the run: a block's corner cut by a diagonal is a real tip.
  const Row above = row(2.45, {2.0, 2.01, 1.995}, {1.998});
  CHECK_FALSE(below_a_straight_run(above.points, above.sides, 0, none, kSigma, kK, kK * kSigma));
  // On a straight slope, within the noise of it.
  const Row slope = row(1.0, {1.5, 2.0, 2.5}, {0.5});
  CHECK_FALSE(below_a_straight_run(slope.points, slope.sides, 0, none, kSigma, kK, kK * kSigma));
  // Below a run that bends (a curved surface): no straight run spans it.
  const Row curved = row(1.55, {2.0, 2.3, 2.8}, {2.2});
  CHECK_FALSE(below_a_straight_run(curved.points, curved.sides, 0, none, kSigma, kK, kK * kSigma));
  // Below by less than three times the line's bound (about 18 sigma here): noise and shape.
  const Row shallow = row(1.85, {2.0, 2.0, 2.0}, {2.0});
  CHECK_FALSE(below_a_straight_run(shallow.points, shallow.sides, 0, none, kSigma, kK, kK * kSigma));
}

TEST(LtsResolution, MarkedPointsAreSkippedAndTooFewLeftIsNoRun) {
  // The run's second point and the other side's first are marked (outliers beside the point): the
  // run is taken from the next ones, still within reach.
  Row r = row(1.55, {2.0, 0.4, 2.01, 1.995}, {3.0, 1.998});
  std::vector<char> marked(r.points.size(), 0);
  marked[2] = 1;  // (2, 0) at 0.4
  marked[5] = 1;  // (-1, 0) at 3.0
  CHECK(below_a_straight_run(r.points, r.sides, 0, marked, kSigma, kK, kK * kSigma));
  // With the run's points marked too, fewer than three are left: no judgement.
  marked[3] = marked[4] = 1;
  CHECK_FALSE(below_a_straight_run(r.points, r.sides, 0, marked, kSigma, kK, kK * kSigma));
}
