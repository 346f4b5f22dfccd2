// Sampling where the part bends: after a coarse grid, which new lines and columns an adaptive scan
// measures next, until every measured point is predicted by its neighbours within the tolerance.
// The points stay a grid (uneven in x and in y), so a tensor-product fit's knots and its
// validation by held-out lines work on them as on any scan.
#pragma once
#include <cstddef>
#include <vector>

#include "host/geometry/point3.h"

namespace dg::host {

// The coarse pass's grid and the finest step refinement may reach (a halving at each level).
struct SamplingGrid {
  double x0_mm = 0, y0_mm = 0;  // the coarse grid's first point
  double x1_mm = 0, y1_mm = 0;  // the extent's far corner
  double step_mm = 1;           // the coarse step, along both axes
  double min_step_mm = 0.25;    // no interval is split below this
  int levels() const;           // how many halvings reach min_step_mm (0: none)
  double unit_mm() const;       // the finest lattice's spacing: step_mm / 2^levels()
};

// A run of new points: count points from (x0_mm, y0_mm) at step_mm along +x, or along +y.
struct SampleRun {
  bool along_y = false;
  double x0_mm = 0, y0_mm = 0, step_mm = 0;
  int count = 0;
};

struct RefinementPlan {
  std::vector<SampleRun> runs;  // the new points, each run's start the nearest to the last one's end
  size_t new_points = 0;
  size_t columns = 0, rows = 0;          // of the grid measured so far
  size_t new_columns = 0, new_rows = 0;  // the plan adds
  size_t intervals_over = 0;    // intervals (between neighbouring columns or rows) beside a point
                                // predicted worse than the tolerance
  size_t intervals_at_min = 0;  // of them, at the finest step already: they stay over
  double worst_mm = 0;          // the largest held-out prediction error of any point
  Point3 worst_at{};            // that point
  double noise_sigma_mm = 0;    // the readings' noise along the rows (fifth differences)
  double noise_miss_mm = 0;     // what that noise alone makes a held-out point miss by: 3 x 1.39 sigma
  // The noise alone makes a held-out point miss by 3 times 1.39 sigma (the cubic's weights) or more
  // than the tolerance: sampling more cannot bring the prediction within it, and the plan is empty.
  bool noise_limited = false;
};

// Every point on the grid's lattice is held out in turn and predicted by a cubic through its two
// nearest neighbours each side along its row, and again along its column (three from one side
// where the other has one; a point at a line's end is not judged along it: no fit's validation
// extrapolates): the same gap a fit's validation leaves when it holds out a line. An interval
// between neighbouring columns beside a point predicted worse than the tolerance along its row
// gets a column at its middle, and likewise rows; the plan measures the new columns at every row
// and the new rows at every column, and any point of that grid not measured yet. Points off the
// lattice are ignored. Where the rows' noise alone would make a held-out point miss by more than
// the tolerance (noise_limited), nothing is planned. The intervals either side of each point of `also_near` (in x and in y) are
// split too: where a fit of the points found its worst error or its validation failed (a point
// with x or y NaN names a line: a crease across the other axis).
RefinementPlan plan_refinement(const std::vector<Point3>& points, const SamplingGrid& grid, double tolerance_mm,
                               const std::vector<Point3>& also_near = {});

}  // namespace dg::host
