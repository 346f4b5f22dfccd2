// Progress text: bar, share, rate and ETA.
#include "host/cli/progress.h"

#include <CppUTest/TestHarness.h>

TEST_GROUP(Progress){};

TEST(Progress, ShowsShareRateAndTimeLeft) {
  STRCMP_EQUAL("[#######.......................]  1250/5000 points   25 %  2.5k points/s  ETA 0:02",
               dg::host::progress_text(1250, 5000, 0.5, true).c_str());
  STRCMP_EQUAL("100/7000 points    1 %  10 points/s  ETA 11:30", dg::host::progress_text(100, 7000, 10, false).c_str());
  STRCMP_EQUAL("0/10 points    0 %  0 points/s  ETA -", dg::host::progress_text(0, 10, 0, false).c_str());
}

TEST(Progress, ACountPastAnEstimatedTotalShowsTheCountAsTheTotal) {
  // A scan on the fly: the total was the grid's estimate and the gauge's cycle gave more points.
  STRCMP_EQUAL("6233/6233 points  100 %  623 points/s  ETA -", dg::host::progress_text(6233, 6231, 10, false).c_str());
}
