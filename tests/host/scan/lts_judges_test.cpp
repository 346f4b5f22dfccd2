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
    t.model[0].ok = true;
    t.model[0].scale = 2.5 * sigma * unit(rng);
    t.model[0].near_worst = 1.0;
    const double bound = k * std::hypot(sigma, t.model[0].scale);
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
