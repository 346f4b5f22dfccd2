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
