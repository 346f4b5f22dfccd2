// Sampling where the part bends, against the simulated parts' true shapes: refinement only where
// held-out points are predicted worse than the tolerance, new points never measured twice, and the
// canister held to 0.01 mm with fewer points than the uniform grid that holds it.
#include "host/scan/adaptive_sampling.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <utility>

#include "hw/sim/parts.h"

namespace {

// The coarse grid of `grid` on `kind`'s true shape, in whole micrometres as the gauge reads.
double reading_mm(dg::sim::PartKind kind, double x_mm, double y_mm) {
  dg::sim::Part part;
  part.kind = kind;
  return std::round(part.height_mm(x_mm, y_mm) * 1e3) * 1e-3;
}

std::vector<dg::host::Point3> coarse(dg::sim::PartKind kind, const dg::host::SamplingGrid& grid) {
  std::vector<dg::host::Point3> points;
  for (double y = grid.y0_mm; y <= grid.y1_mm + 1e-9; y += grid.step_mm) {
    for (double x = grid.x0_mm; x <= grid.x1_mm + 1e-9; x += grid.step_mm) points.push_back({x, y, reading_mm(kind, x, y)});
  }
  return points;
}

// Measures every run of the plan on the true shape; false when a new point was measured before.
bool measure(dg::sim::PartKind kind, const dg::host::RefinementPlan& plan, std::vector<dg::host::Point3>* points) {
  std::set<std::pair<long, long>> seen;
  for (const auto& p : *points) seen.insert({std::lround(p.x * 1e4), std::lround(p.y * 1e4)});
  for (const auto& run : plan.runs) {
    for (int k = 0; k < run.count; ++k) {
      const double x = run.x0_mm + (run.along_y ? 0 : k * run.step_mm), y = run.y0_mm + (run.along_y ? k * run.step_mm : 0);
      if (!seen.insert({std::lround(x * 1e4), std::lround(y * 1e4)}).second) return false;
      points->push_back({x, y, reading_mm(kind, x, y)});
    }
  }
  return true;
}

dg::host::SamplingGrid canister_grid(double step_mm, double min_step_mm) {
  dg::host::SamplingGrid grid;
  grid.x1_mm = 40;
  grid.y1_mm = 30;
  grid.step_mm = step_mm;
  grid.min_step_mm = min_step_mm;
  return grid;
}

}  // namespace

TEST_GROUP(AdaptiveSampling){};

TEST(AdaptiveSampling, HalvesTheCoarseStepDownToTheFinest) {
  const dg::host::SamplingGrid grid = canister_grid(2, 0.25);
  LONGS_EQUAL(3, grid.levels());
  DOUBLES_EQUAL(0.25, grid.unit_mm(), 1e-12);
  LONGS_EQUAL(0, canister_grid(2, 2).levels());
  LONGS_EQUAL(2, canister_grid(2, 0.3).levels());
}

TEST(AdaptiveSampling, AFlatPartNeedsNothingMore) {
  dg::host::SamplingGrid grid = canister_grid(2, 0.25);
  const dg::host::RefinementPlan plan = plan_refinement(coarse(dg::sim::PartKind::kFlat, grid), grid, 0.01);
  LONGS_EQUAL(0, plan.runs.size());
  LONGS_EQUAL(21, plan.columns);
  LONGS_EQUAL(16, plan.rows);
  LONGS_EQUAL(0, plan.intervals_over);
}

TEST(AdaptiveSampling, RefinesTheCanisterWhereItBendsUntilEveryPointIsPredictedWithinTheTolerance) {
  const dg::host::SamplingGrid grid = canister_grid(2, 0.25);
  std::vector<dg::host::Point3> points = coarse(dg::sim::PartKind::kCanister, grid);
  const size_t coarse_points = points.size();
  dg::host::RefinementPlan plan = plan_refinement(points, grid, 0.01);
  CHECK(plan.intervals_over > 0);
  // The canister bends across its dish and its rounded long edges: some columns and rows, not all.
  std::printf("\n  round 1: %zu new columns, %zu new rows, worst %.4f at (%.2f, %.2f)\n", plan.new_columns, plan.new_rows, plan.worst_mm, plan.worst_at.x, plan.worst_at.y);
  CHECK(plan.new_columns < 20);
  CHECK(plan.new_rows > 0 && plan.new_rows < 15);
  int passes = 0;
  while (!plan.runs.empty() && passes < 10) {
    CHECK(measure(dg::sim::PartKind::kCanister, plan, &points));
    plan = plan_refinement(points, grid, 0.01);
    ++passes;
  }
  LONGS_EQUAL(0, plan.runs.size());
  CHECK(passes <= grid.levels());
  // What stays over the tolerance is only at the finest step.
  LONGS_EQUAL(plan.intervals_at_min, plan.intervals_over);
  // Still a grid: every column at every row.
  LONGS_EQUAL(plan.columns * plan.rows, points.size());
  CHECK(points.size() > coarse_points);

  CHECK(plan.worst_mm <= 0.01);

  // The coarsest uniform grid whose own held-out check keeps 0.01 mm: the adaptive scan has less
  // than half its points.
  size_t uniform_points = 0;
  for (double h : {2.0, 1.0, 0.5, 0.25}) {
    const dg::host::SamplingGrid g = canister_grid(h, h);
    const std::vector<dg::host::Point3> grid_points = coarse(dg::sim::PartKind::kCanister, g);
    if (plan_refinement(grid_points, g, 0.01).worst_mm <= 0.01) {
      uniform_points = grid_points.size();
      break;
    }
  }
  CHECK(uniform_points > 0);
  CHECK(points.size() * 2 < uniform_points);
}
