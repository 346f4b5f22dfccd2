// The LTS filter's window models: a subset that is already the h smallest of a window is told
// without a selection.
#include "host/scan/lts_models.h"

#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

using dg::host::lts::keeps_mask;
using dg::host::lts::Ranked;

TEST_GROUP(LtsModels){};

// Against nth_element on random windows, ties in the residual included (readings in whole
// micrometres make them): the mask of the h smallest is kept, and any other mask of h is not.
TEST(LtsModels, KeepsMaskAgreesWithTheSelectionOfTheSmallest) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = 6 + static_cast<int>(rng() % 59);
    const int h = 1 + static_cast<int>(rng() % static_cast<unsigned>(n));
    std::vector<Ranked> ranked;
    for (int m = 0; m < n; ++m) {
      // Few distinct residuals, so that ties are common; point numbers in shuffled order.
      ranked.push_back({static_cast<double>(rng() % 5), static_cast<size_t>(rng() % 1000) * 64 + static_cast<size_t>(m),
                        static_cast<unsigned>(m)});
    }
    std::vector<Ranked> selected = ranked;
    std::nth_element(selected.begin(), selected.begin() + (h - 1), selected.end());
    uint64_t smallest = 0;
    for (int m = 0; m < h; ++m) smallest |= uint64_t{1} << selected[static_cast<size_t>(m)].position;
    CHECK(keeps_mask(ranked, smallest));
    if (h == n) continue;
    // Swap one place in for one out: no longer the h smallest (point numbers break every tie).
    const unsigned in = selected[static_cast<size_t>(rng() % static_cast<unsigned>(h))].position;
    const unsigned out = selected[static_cast<size_t>(h + static_cast<int>(rng() % static_cast<unsigned>(n - h)))].position;
    CHECK_FALSE(keeps_mask(ranked, (smallest & ~(uint64_t{1} << in)) | uint64_t{1} << out));
  }
}
