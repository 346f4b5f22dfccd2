// The nearest point on another scan line, found by halves along the lines' direction.
#include "host/scan/sorted_lines.h"

#include <CppUTest/TestHarness.h>

#include <vector>

TEST_GROUP(SortedLines){};

// Two lines given out of order (a serpentine's second line runs backwards), with positions along
// them: each point's nearest on the other line, the later on a tie, the ends past either end,
// and -1 for an empty line.
TEST(SortedLines, FindsTheNearestPointOfAnotherLineAlongThem) {
  const std::vector<double> t = {0.0, 1.0, 2.0, 3.0, 2.5, 1.5, 0.5, -1.0};
  auto along = [&](size_t i) { return t[i]; };
  const dg::host::SortedLines<decltype(along)> lines({{3, 0, 2, 1}, {7, 4, 6, 5}, {}}, along);
  LONGS_EQUAL(3, lines.size());
  CHECK((lines.line(0) == std::vector<size_t>{0, 1, 2, 3}));
  CHECK((lines.line(1) == std::vector<size_t>{7, 6, 5, 4}));
  LONGS_EQUAL(5, lines.nearest_on(1, 1));  // 1.0 lies halfway between 0.5 and 1.5: the later
  LONGS_EQUAL(4, lines.nearest_on(1, 3));  // 3.0 beyond the line's end at 2.5
  LONGS_EQUAL(6, lines.nearest_on(1, 0));  // 0.0: -1.0 is 1.0 away, 0.5 only 0.5
  LONGS_EQUAL(0, lines.nearest_on(0, 7));  // -1.0 before the line's start
  LONGS_EQUAL(-1, lines.nearest_on(2, 0));
}
