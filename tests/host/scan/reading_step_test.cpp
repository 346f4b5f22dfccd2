// The reading step found in the heights: whole micrometres, and none in unrounded values.
#include "host/scan/reading_step.h"

#include <CppUTest/TestHarness.h>

#include "tests/support/part_scan.h"

using namespace dg::host;

TEST_GROUP(ReadingStep){};

TEST(ReadingStep, FindsTheStepTheReadingsAreRoundedTo) {
  dg::test::PartScan s;
  s.kind = dg::sim::PartKind::kCanister;
  s.sigma_um = 2;
  s.step_um = 1;
  DOUBLES_EQUAL(0.001, detect_resolution_mm(dg::test::scan_part(s, 3).points), 1e-12);
  s.step_um = 5;
  DOUBLES_EQUAL(0.005, detect_resolution_mm(dg::test::scan_part(s, 3).points), 1e-12);
  s.step_um = 0;
  DOUBLES_EQUAL(0.0, detect_resolution_mm(dg::test::scan_part(s, 3).points), 0.0);
}

TEST(ReadingStep, AFlatReadAlikeAlmostEverywhereHasTheStepItsFewOtherReadingsShow) {
  // 0.3 um of noise on 1 um readings: nine in ten read the same 5.000 mm, a whole multiple of every
  // usual step; the readings a step off tell the step.
  dg::test::PartScan s;
  s.kind = dg::sim::PartKind::kFlat;
  s.sigma_um = 0.3;
  DOUBLES_EQUAL(0.001, detect_resolution_mm(dg::test::scan_part(s, 5).points), 1e-12);
  // Every reading alike: no step can be told.
  s.sigma_um = 0;
  DOUBLES_EQUAL(0.0, detect_resolution_mm(dg::test::scan_part(s, 5).points), 0.0);
}
