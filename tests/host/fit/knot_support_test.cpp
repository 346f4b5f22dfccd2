// Whether the data can determine a net: the Schoenberg-Whitney condition along each direction, the
// straight ramps over data-free C0 spans, and the matching over the whole tensor-product net.
#include <CppUTest/TestHarness.h>

#include <functional>
#include <random>
#include <vector>

#include "common/fit/bspline_basis.h"
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
  const std::vector<UV> uv = grid(20, 15);
  CHECK(none == unmatched_control_point(clamped_uniform_knots(12, 3), 3, clamped_uniform_knots(10, 3), 3, SiteIndex(uv)));
}

TEST(KnotSupport, AHoleInTheCornerLeavesTheCornerControlPointWithoutAPoint) {
  // Each direction still has every u and v position (the rows and columns pass the hole), but
  // nothing lies under the corner control points.
  const std::vector<UV> uv = grid(20, 15, 0.8, 0.8, 1.0, 1.0);
  const auto knots_u = clamped_uniform_knots(12, 3), knots_v = clamped_uniform_knots(10, 3);
  LONGS_EQUAL(-1, schoenberg_whitney_gap(knots_u, 3, distinct_sites(uv, true, site_merge_distance(uv.size()))));
  LONGS_EQUAL(-1, schoenberg_whitney_gap(knots_v, 3, distinct_sites(uv, false, site_merge_distance(uv.size()))));
  const std::pair<int, int> hole = unmatched_control_point(knots_u, 3, knots_v, 3, SiteIndex(uv));
  CHECK(hole.first >= 9 && hole.second >= 7);
}

TEST(KnotSupport, AMarginRefusesControlPointsSeenOnlyAtTheTailOfTheirSupport) {
  // The corner hole is small enough that its control point still touches points at its support's
  // tail: determined, but weakly; with a margin of 0.01 on N_i N_j it is refused.
  const std::vector<UV> uv = grid(20, 15, 0.9, 0.9, 1.0, 1.0);
  const auto knots_u = clamped_uniform_knots(12, 3), knots_v = clamped_uniform_knots(10, 3);
  const std::pair<int, int> none{-1, -1};
  const SiteIndex index(uv);
  CHECK(none == unmatched_control_point(knots_u, 3, knots_v, 3, index, 0.0));
  CHECK(none != unmatched_control_point(knots_u, 3, knots_v, 3, index, 0.01));
}

namespace {

// The first control point (in i, j order) that a maximum matching over every point leaves without
// one of its own: Kuhn's algorithm on the whole graph, the textbook form, as the oracle.
std::pair<int, int> unmatched_over_all_points(const std::vector<double>& knots_u, const std::vector<double>& knots_v,
                                              const std::vector<UV>& uv, double min_product) {
  const int count_u = static_cast<int>(knots_u.size()) - 4, count_v = static_cast<int>(knots_v.size()) - 4;
  std::vector<std::vector<int>> points_of(static_cast<size_t>(count_u * count_v));
  for (size_t k = 0; k < uv.size(); ++k) {
    const int su = dg::fit::find_span(count_u, 3, uv[k].u, knots_u.data());
    const int sv = dg::fit::find_span(count_v, 3, uv[k].v, knots_v.data());
    double nu[4], nv[4];
    dg::fit::bspline_basis(su, 3, uv[k].u, knots_u.data(), nu);
    dg::fit::bspline_basis(sv, 3, uv[k].v, knots_v.data(), nv);
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) {
        if (nu[a] * nv[b] > min_product) points_of[static_cast<size_t>((su - 3 + a) * count_v + sv - 3 + b)].push_back(static_cast<int>(k));
      }
    }
  }
  std::vector<int> owner(uv.size(), -1), seen(uv.size(), -1);
  std::function<bool(int, int)> augment = [&](int c, int stamp) {
    for (int k : points_of[static_cast<size_t>(c)]) {
      if (seen[static_cast<size_t>(k)] == stamp) continue;
      seen[static_cast<size_t>(k)] = stamp;
      if (owner[static_cast<size_t>(k)] < 0 || augment(owner[static_cast<size_t>(k)], stamp)) {
        owner[static_cast<size_t>(k)] = c;
        return true;
      }
    }
    return false;
  };
  for (int c = 0; c < count_u * count_v; ++c) {
    if (!augment(c, c)) return {c / count_v, c % count_v};
  }
  return {-1, -1};
}

}  // namespace

TEST(KnotSupport, TheMatchingOnAFewPointsPerControlPointAgreesWithTheMatchingOverAllPoints) {
  // Dense random points (hundreds per control point, so each keeps only its cap) with random
  // holes: one hole beside a corner, thin slots, nearly empty spans. The capped matching must
  // find the same first unmatched control point as the matching over every point, or none.
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int failures_seen = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int count_u = 5 + trial % 7, count_v = 4 + trial % 5;
    const double hole_u0 = unit(rng), hole_v0 = unit(rng);
    const double hole_u1 = hole_u0 + 0.6 * unit(rng), hole_v1 = hole_v0 + 0.6 * unit(rng);
    std::vector<UV> uv;
    const int n = trial % 2 == 0 ? 400 + 200 * (trial % 4) : 30 + 10 * (trial % 5);
    for (int k = 0; k < n; ++k) {
      const UV p{unit(rng), unit(rng)};
      if (p.u > hole_u0 && p.u < hole_u1 && p.v > hole_v0 && p.v < hole_v1) continue;
      uv.push_back(p);
    }
    const auto knots_u = clamped_uniform_knots(count_u, 3), knots_v = clamped_uniform_knots(count_v, 3);
    for (double min_product : {0.0, 0.01}) {
      const std::pair<int, int> expected = unmatched_over_all_points(knots_u, knots_v, uv, min_product);
      if (expected.first >= 0) ++failures_seen;
      const std::pair<int, int> got = unmatched_control_point(knots_u, 3, knots_v, 3, SiteIndex(uv), min_product);
      LONGS_EQUAL(expected.first, got.first);
      LONGS_EQUAL(expected.second, got.second);
    }
  }
  CHECK(failures_seen >= 10);  // the trials exercise refusals as well as matchings
}
