// The deviations' histogram: every point in one bar, the tolerance's limits drawn where they lie.
#include "host/inspect/histogram.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <regex>
#include <string>
#include "tests/support/inspection_at.h"

using namespace dg::host;
using dg::test::at_deviations;

namespace {

size_t bars_total(const std::string& svg, size_t* bars) {
  const std::regex count("class=\"bar\" data-count=\"([0-9]+)\"");
  size_t total = 0;
  *bars = 0;
  for (auto m = std::sregex_iterator(svg.begin(), svg.end(), count); m != std::sregex_iterator(); ++m) {
    total += std::stoul((*m)[1]);
    ++*bars;
  }
  return total;
}

}  // namespace

TEST_GROUP(Histogram){};

TEST(Histogram, EveryPointIsInOneBar) {
  std::vector<double> d;
  for (int i = 0; i < 1000; ++i) d.push_back(0.01 * std::sin(i * 0.7) + (i == 5 ? 0.3 : 0.0));
  size_t bars = 0;
  const std::string svg = deviation_histogram_svg(at_deviations(d), nullptr, 40);
  LONGS_EQUAL(1000, bars_total(svg, &bars));
  LONGS_EQUAL(40, bars);
  CHECK(svg.find("class=\"limit\"") == std::string::npos);
  CHECK(svg.find("signed orthogonal deviation, mm") != std::string::npos);
}

TEST(Histogram, TheLimitsAndTheBandsOfUncertaintyAreDrawnAroundThePoints) {
  const Inspection r = at_deviations({0.001, -0.002, 0.003});
  const Decision d = decide(r, ToleranceLimits{-0.02, 0.05}, {0.002, 0.002, 0.002}, "test");
  const std::string svg = deviation_histogram_svg(r, &d, 30);
  size_t bars = 0;
  LONGS_EQUAL(3, bars_total(svg, &bars));
  // Both limits, labelled, and a band of U at each.
  const std::regex limit("class=\"limit\"");
  LONGS_EQUAL(2, std::distance(std::sregex_iterator(svg.begin(), svg.end(), limit), std::sregex_iterator()));
  const std::regex band("class=\"uncertainty\"");
  LONGS_EQUAL(2, std::distance(std::sregex_iterator(svg.begin(), svg.end(), band), std::sregex_iterator()));
  CHECK(svg.find(">-0.02</text>") != std::string::npos);
  CHECK(svg.find(">0.05</text>") != std::string::npos);
}
