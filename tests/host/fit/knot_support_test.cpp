// Whether the data can determine a net: the Schoenberg-Whitney condition along each direction, the
// straight ramps over data-free C0 spans, and the matching over the whole tensor-product net.
#include <CppUTest/TestHarness.h>

#include <vector>

#include "host/fit/knot_support.h"
#include "host/geometry/bspline_surface.h"

using namespace dg::host;

namespace {

// An n x m grid of parameters over [0, 1]^2, less the points inside the box (u0, v0)..(u1, v1).
std::vector<UV> grid(int n, int m, double u0 = 2, double v0 = 2, double u1 = -1, double v1 = -1) {
  std::vector<UV> out;
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) {
      const double u = static_cast<double>(i) / (n - 1), v = static_cast<double>(j) / (m - 1);
      if (u >= u0 && u <= u1 && v >= v0 && v <= v1) continue;
      out.push_back({u, v});
    }
  }
  return out;
}

std::vector<double> even_sites(int n) {
  std::vector<double> out;
  for (int i = 0; i < n; ++i) out.push_back(static_cast<double>(i) / (n - 1));
  return out;
}

}  // namespace

TEST_GROUP(KnotSupport){};

TEST(KnotSupport, AsManyControlPointsAsSitesHoldsAndOneMoreFails) {
  LONGS_EQUAL(-1, schoenberg_whitney_gap(clamped_uniform_knots(10, 3), 3, even_sites(10)));
  CHECK(schoenberg_whitney_gap(clamped_uniform_knots(11, 3), 3, even_sites(10)) >= 0);
}

TEST(KnotSupport, SitesCrowdedAtOneEndLeaveAControlPointAtTheOtherWithout) {
  std::vector<double> sites;
  for (int i = 0; i < 12; ++i) sites.push_back(0.04 * i);  // all in [0, 0.44]
  sites.push_back(1.0);
  CHECK(schoenberg_whitney_gap(clamped_uniform_knots(8, 3), 3, sites) >= 0);
}

TEST(KnotSupport, TheLinesOfOneScanCountAsOneSiteEach) {
  std::vector<UV> uv;
  for (int line = 0; line < 5; ++line) {
    for (int k = 0; k < 40; ++k) uv.push_back({k / 39.0, line / 4.0 + 1e-5 * (k % 3)});  // jitter along v
  }
  const std::vector<double> v_sites = distinct_sites(uv, false, site_merge_distance(uv.size()));
  LONGS_EQUAL(5, v_sites.size());
}

TEST(KnotSupport, ADataFreeSpanBetweenTwoC0KnotsIsAStraightRamp) {
  // Degree 3, knots with multiplicity 3 at 0.4 and 0.6 and no site between them.
  const std::vector<double> knots = {0, 0, 0, 0, 0.2, 0.4, 0.4, 0.4, 0.6, 0.6, 0.6, 0.8, 1, 1, 1, 1};
  std::vector<double> sites;
  for (double s : even_sites(21)) {
    if (s < 0.4 - 1e-9 || s > 0.6 + 1e-9) sites.push_back(s);
  }
  const std::vector<RampPoint> ramps = ramp_points(knots, 3, sites);
  LONGS_EQUAL(2, ramps.size());
  LONGS_EQUAL(ramps[0].left, ramps[1].left);
  LONGS_EQUAL(ramps[0].right, ramps[1].right);
  CHECK(ramps[0].weight_right > 0 && ramps[0].weight_right < ramps[1].weight_right && ramps[1].weight_right < 1);
  // The ramp's inner points need no site: the rest of the net is determined.
  LONGS_EQUAL(-1, schoenberg_whitney_gap(knots, 3, sites));
}

TEST(KnotSupport, AFullGridGivesEveryControlPointAPointOfItsOwn) {
  const std::pair<int, int> none{-1, -1};
  CHECK(none == unmatched_control_point(clamped_uniform_knots(12, 3), 3, clamped_uniform_knots(10, 3), 3, grid(20, 15)));
}

TEST(KnotSupport, AHoleInTheCornerLeavesTheCornerControlPointWithoutAPoint) {
  // Each direction still has every u and v position (the rows and columns pass the hole), but
  // nothing lies under the corner control points.
  const std::vector<UV> uv = grid(20, 15, 0.8, 0.8, 1.0, 1.0);
  const auto knots_u = clamped_uniform_knots(12, 3), knots_v = clamped_uniform_knots(10, 3);
  LONGS_EQUAL(-1, schoenberg_whitney_gap(knots_u, 3, distinct_sites(uv, true, site_merge_distance(uv.size()))));
  LONGS_EQUAL(-1, schoenberg_whitney_gap(knots_v, 3, distinct_sites(uv, false, site_merge_distance(uv.size()))));
  const std::pair<int, int> hole = unmatched_control_point(knots_u, 3, knots_v, 3, uv);
  CHECK(hole.first >= 9 && hole.second >= 7);
}

TEST(KnotSupport, AMarginRefusesControlPointsSeenOnlyAtTheTailOfTheirSupport) {
  // The corner hole is small enough that its control point still touches points at its support's
  // tail: determined, but weakly; with a margin of 0.01 on N_i N_j it is refused.
  const std::vector<UV> uv = grid(20, 15, 0.9, 0.9, 1.0, 1.0);
  const auto knots_u = clamped_uniform_knots(12, 3), knots_v = clamped_uniform_knots(10, 3);
  const std::pair<int, int> none{-1, -1};
  CHECK(none == unmatched_control_point(knots_u, 3, knots_v, 3, uv, 0.0));
  CHECK(none != unmatched_control_point(knots_u, 3, knots_v, 3, uv, 0.01));
}
