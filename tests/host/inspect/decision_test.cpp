// ISO 14253-1's decision rule per point: pass only inside the tolerance shrunk by U, fail only
// outside it widened by U, inconclusive between; the part fails if any point does.
#include "host/inspect/decision.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <stdexcept>

#include "host/inspect/inspection_json.h"
#include <nlohmann/json.hpp>
#include "tests/support/inspection_at.h"

using namespace dg::host;
using dg::test::at_deviations;

TEST_GROUP(Decision){};

TEST(Decision, PassesOnlyInsideTheShrunkZoneAndFailsOnlyOutsideTheWidenedOne) {
  // +-0.05 mm with u = 0.005 (U = 0.01): pass to 0.04, fail beyond 0.06.
  const Inspection r = at_deviations({0.03, 0.04, 0.045, 0.06, 0.065, -0.061, -0.0399});
  const Decision d = decide(r, ToleranceLimits{-0.05, 0.05}, std::vector<double>(7, 0.005), "test");
  CHECK(d.points[0] == Verdict::kPass);
  CHECK(d.points[1] == Verdict::kPass);           // on the shrunk limit: conformance proven
  CHECK(d.points[2] == Verdict::kInconclusive);
  CHECK(d.points[3] == Verdict::kInconclusive);   // on the widened limit: not proven out
  CHECK(d.points[4] == Verdict::kFail);
  CHECK(d.points[5] == Verdict::kFail);
  CHECK(d.points[6] == Verdict::kPass);
  LONGS_EQUAL(3, d.pass);
  LONGS_EQUAL(2, d.fail);
  LONGS_EQUAL(2, d.inconclusive);
  CHECK(d.verdict == Verdict::kFail);
  DOUBLES_EQUAL(0.01, d.max_expanded_mm, 1e-15);
  // The failing points first, the farthest past its limit first, then the inconclusive ones.
  LONGS_EQUAL(4, d.worst.size());
  LONGS_EQUAL(4, d.worst[0]);
  LONGS_EQUAL(5, d.worst[1]);
  LONGS_EQUAL(3, d.worst[2]);
  LONGS_EQUAL(2, d.worst[3]);
}

TEST(Decision, APartIsInconclusiveWhenNoPointFailsButOneIsNotProvenIn) {
  const Inspection r = at_deviations({0.001, 0.012, -0.002});
  // Asymmetric limits -0.005..+0.015 with U = 0.004: 0.012 is within, but not by U.
  const Decision d = decide(r, ToleranceLimits{-0.005, 0.015}, {0.002, 0.002, 0.002}, "test");
  CHECK(d.verdict == Verdict::kInconclusive);
  const Decision exact = decide(r, ToleranceLimits{-0.005, 0.015}, {0, 0, 0}, "exact");
  CHECK(exact.verdict == Verdict::kPass);
  LONGS_EQUAL(0, exact.worst.size());
}

// A point beyond the surface's edge proves nothing: inconclusive whether its distance to the edge
// is inside the tolerance or far outside it, and counted as such.
TEST(Decision, APointBeyondTheSurfacesEdgeIsInconclusiveWhateverItsDistance) {
  Inspection r = at_deviations({0.001, 0.002, 0.5, -0.001, 0.0495});
  r.points[1].beyond_edge = true;
  r.points[2].beyond_edge = true;
  const Decision d = decide(r, ToleranceLimits{-0.05, 0.05}, std::vector<double>(5, 0.001), "test");
  CHECK(d.points[0] == Verdict::kPass);
  CHECK(d.points[1] == Verdict::kInconclusive);
  CHECK(d.points[2] == Verdict::kInconclusive);
  CHECK(d.points[3] == Verdict::kPass);
  CHECK(d.points[4] == Verdict::kInconclusive);
  LONGS_EQUAL(0, d.fail);
  LONGS_EQUAL(3, d.inconclusive);
  LONGS_EQUAL(2, d.beyond_edge);
  CHECK(d.verdict == Verdict::kInconclusive);
  // The point over the surface first among the inconclusive, though 0.5 mm is farther past the limit.
  LONGS_EQUAL(3, d.worst.size());
  LONGS_EQUAL(4, d.worst[0]);
  LONGS_EQUAL(2, d.worst[1]);
  LONGS_EQUAL(1, d.worst[2]);
  const nlohmann::json j = nlohmann::json::parse(inspection_json_text(r, "p.csv", "s.json", nullptr, &d));
  LONGS_EQUAL(2, j["decision"]["inconclusive_beyond_edge"].get<int>());
  CHECK_FALSE(j["decision"]["worst"][0]["beyond_edge"].get<bool>());
  CHECK(j["decision"]["worst"][1]["beyond_edge"].get<bool>());
}

TEST(Decision, RefusesLimitsTheWrongWayRoundAndUncertaintiesThatAreNotNumbers) {
  const Inspection r = at_deviations({0.0});
  CHECK_THROWS(std::invalid_argument, decide(r, ToleranceLimits{0.05, -0.05}, {0.001}, ""));
  CHECK_THROWS(std::invalid_argument, decide(r, ToleranceLimits{-0.05, NAN}, {0.001}, ""));
  CHECK_THROWS(std::invalid_argument, decide(r, ToleranceLimits{-0.05, 0.05}, {NAN}, ""));
  CHECK_THROWS(std::invalid_argument, decide(r, ToleranceLimits{-0.05, 0.05}, {-0.001}, ""));
  CHECK_THROWS(std::invalid_argument, decide(r, ToleranceLimits{-0.05, 0.05}, {}, ""));
}

TEST(Decision, TheJsonCarriesTheVerdictCountsAndTheWorstPoints) {
  const Inspection r = at_deviations({0.03, 0.07});
  const Decision d = decide(r, ToleranceLimits{-0.05, 0.05}, {0.005, 0.005}, "the points' sigma column");
  const nlohmann::json j = nlohmann::json::parse(inspection_json_text(r, "p.csv", "s.json", nullptr, &d));
  STRCMP_EQUAL("fail", j["decision"]["verdict"].get<std::string>().c_str());
  LONGS_EQUAL(1, j["decision"]["fail"].get<int>());
  LONGS_EQUAL(2, j["decision"]["worst"][0]["point"].get<int>());
  DOUBLES_EQUAL(0.07, j["decision"]["worst"][0]["deviation"].get<double>(), 0);
  CHECK(nlohmann::json::parse(inspection_json_text(r, "p.csv", "s.json"))["decision"].is_null());
}

// A zone decides its points with its own limits (the first zone that holds a point), the rest go
// by the general tolerance; each zone has its counts and verdict, and the part's verdict is over all.
TEST(Decision, AZoneDecidesItsPointsWithItsOwnTolerance) {
  // x = 0..5; u = 0.001 (U = 0.002). Zone "seal" holds x 1..2 with +-0.01, zone "wide" x 2..4 with
  // -0.1..+0.1 (x = 2 is in both: the first listed decides it).
  const Inspection r = at_deviations({0.03, 0.005, 0.02, 0.09, 0.03, 0.07});
  ToleranceZone seal{"seal", 0.5, 2.0, -1, 1, {-0.01, 0.01}};
  ToleranceZone wide{"wide", 2.0, 4.0, -1, 1, {-0.1, 0.1}};
  const Decision d = decide(r, ToleranceLimits{-0.05, 0.05}, std::vector<double>(6, 0.001), "test", {seal, wide});
  CHECK(d.points[0] == Verdict::kPass);   // general: 0.03 within 0.05
  CHECK(d.points[1] == Verdict::kPass);   // seal: 0.005 within 0.01 - 0.002
  CHECK(d.points[2] == Verdict::kFail);   // seal (first listed): 0.02 beyond 0.012
  CHECK(d.points[3] == Verdict::kPass);   // wide: 0.09 within 0.1 - 0.002
  CHECK(d.points[4] == Verdict::kPass);   // wide
  CHECK(d.points[5] == Verdict::kFail);   // general: 0.07 beyond 0.052
  LONGS_EQUAL(3, d.zones.size());
  STRCMP_EQUAL("seal", d.zones[0].zone.name.c_str());
  LONGS_EQUAL(1, d.zones[0].pass);
  LONGS_EQUAL(1, d.zones[0].fail);
  CHECK(d.zones[0].verdict == Verdict::kFail);
  LONGS_EQUAL(2, d.zones[1].pass);
  CHECK(d.zones[1].verdict == Verdict::kPass);
  STRCMP_EQUAL("elsewhere", d.zones[2].zone.name.c_str());
  LONGS_EQUAL(1, d.zones[2].pass);
  LONGS_EQUAL(1, d.zones[2].fail);
  LONGS_EQUAL(2, d.zone_of_point[0]);
  LONGS_EQUAL(0, d.zone_of_point[2]);
  CHECK(d.verdict == Verdict::kFail);
  const nlohmann::json j = nlohmann::json::parse(inspection_json_text(r, "p.csv", "s.json", nullptr, &d));
  STRCMP_EQUAL("seal", j["decision"]["zones"][0]["name"].get<std::string>().c_str());
  DOUBLES_EQUAL(0.5, j["decision"]["zones"][0]["box_mm"][0][0].get<double>(), 0);
  CHECK(!j["decision"]["zones"][2].contains("box_mm"));
  // The worst first: point 6 is 0.02 past the general limit, point 3 0.01 past the seal's.
  STRCMP_EQUAL("elsewhere", j["decision"]["worst"][0]["zone"].get<std::string>().c_str());
  LONGS_EQUAL(3, j["decision"]["worst"][1]["point"].get<int>());
  STRCMP_EQUAL("seal", j["decision"]["worst"][1]["zone"].get<std::string>().c_str());
}

// A zone that holds no point is refused by name: a box given in the wrong coordinates would
// otherwise let its points be judged by the looser general tolerance without a word.
TEST(Decision, AZoneThatHoldsNoPointIsRefusedByName) {
  const Inspection r = at_deviations({0.0, 0.0});
  ToleranceZone away{"boss-3", 50, 60, -1, 1, {-0.01, 0.01}};
  try {
    decide(r, ToleranceLimits{-0.05, 0.05}, {0.001, 0.001}, "test", {away});
    FAIL("an empty zone was accepted");
  } catch (const std::invalid_argument& e) {
    STRCMP_CONTAINS("zone boss-3 holds none of the points", e.what());
  }
  ToleranceZone inverted{"flat", 1, 0, -1, 1, {-0.01, 0.01}};
  CHECK_THROWS(std::invalid_argument, decide(r, ToleranceLimits{-0.05, 0.05}, {0.001, 0.001}, "test", {inverted}));
}
