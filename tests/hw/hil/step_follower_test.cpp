// The HIL rig's step counting: STEP rises counted by DIR's level at that instant, edges merged by
// their timestamps across lines.
#include <CppUTest/TestHarness.h>

#include <vector>

#include "hw/hil/step_follower.h"

using dg::hil::AxisLine;
using dg::hil::Edge;
using dg::hil::StepFollower;

TEST_GROUP(StepFollower) {};

TEST(StepFollower, CountsRisingStepEdgesInTheDirectionDirGives) {
  StepFollower table(100, -5, true, false);
  std::vector<Edge> edges;
  for (uint64_t t = 0; t < 10; ++t) {
    edges.push_back({t * 1000, 0, AxisLine::kStep, true});
    edges.push_back({t * 1000 + 500, 0, AxisLine::kStep, false});  // falling edges move nothing
  }
  edges.push_back({20000, 1, AxisLine::kStep, true});
  table.apply(edges);
  LONGS_EQUAL(110, table.x_steps());
  LONGS_EQUAL(-6, table.y_steps());
  LONGS_EQUAL(11, table.steps());
  CHECK(edges.empty());
}

TEST(StepFollower, ADirChangeReadAfterTheStepsStillCountsThemTheWayTheyWent) {
  StepFollower table(0, 0, true, true);
  // Read line by line: all STEP edges first, then the DIR edge that came between them.
  std::vector<Edge> edges = {{1000, 0, AxisLine::kStep, true}, {2000, 0, AxisLine::kStep, true},
                             {4000, 0, AxisLine::kStep, true}, {5000, 0, AxisLine::kStep, true},
                             {6000, 0, AxisLine::kStep, true}, {3000, 0, AxisLine::kDir, false}};
  table.apply(edges);
  LONGS_EQUAL(2 - 3, table.x_steps());
  LONGS_EQUAL(0, table.y_steps());
}

TEST(StepFollower, TheAxesKeepTheirOwnDirection) {
  StepFollower table(0, 0, true, true);
  std::vector<Edge> edges = {{10, 1, AxisLine::kDir, false}, {20, 0, AxisLine::kStep, true}, {30, 1, AxisLine::kStep, true}};
  table.apply(edges);
  LONGS_EQUAL(1, table.x_steps());
  LONGS_EQUAL(-1, table.y_steps());
  // Later batches go on from where the last one left the DIR lines.
  edges = {{40, 1, AxisLine::kStep, true}};
  table.apply(edges);
  LONGS_EQUAL(-2, table.y_steps());
}

TEST(StepFollower, EdgesOfAnAxisThatDoesNotExistAreIgnored) {
  StepFollower table(0, 0, true, true);
  std::vector<Edge> edges = {{10, 2, AxisLine::kStep, true}, {20, -1, AxisLine::kStep, true}};
  table.apply(edges);
  LONGS_EQUAL(0, table.x_steps());
  LONGS_EQUAL(0, table.y_steps());
  LONGS_EQUAL(0, table.steps());
}

TEST(StepFollower, TellsWhatDirShouldReadOncePendingEdgesAreApplied) {
  StepFollower table(0, 0, true, false);
  std::vector<Edge> pending = {{30, 0, AxisLine::kDir, true}, {10, 0, AxisLine::kDir, false}, {20, 1, AxisLine::kDir, true}};
  CHECK(table.dir_after(pending, 0));  // the latest x edge, whatever the order read
  CHECK(table.dir_after(pending, 1));
  pending.clear();
  CHECK(table.dir_after(pending, 0));
  CHECK_FALSE(table.dir_after(pending, 1));
}
