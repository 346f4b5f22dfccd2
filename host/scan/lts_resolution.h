// Whether a scan's grid resolves the surface around a point the LTS judges condemned: where no model
// of its neighbours describes them, the point's height cannot be told from the part's shape.
#pragma once
#include <cstddef>
#include <vector>

#include "host/geometry/point3.h"
#include "host/scan/lts_grid.h"

namespace dg::host::lts {

// Marked points in 8-connected groups (along the rows, columns and diagonals of the grid) of at
// most `max_size`: outliers, alone or as pairs, triples and chance neighbours (among 5 % of them
// mostly up to four; the flat's seed 9 at 2 um has two chains of five, whose points the half-planes
// and lines here keep in their fits); a band of real points the judges condemned makes longer ones.
constexpr size_t kOutlierGroupMax = 4;
std::vector<char> in_small_groups(const std::vector<LineSides>& sides, const std::vector<char>& marked, size_t max_size);

// A condemned point is judged again only where its own whole window misses its points by more than
// this many sigmas: a curved part that a cubic follows a little worse than the noise (the
// canister's dish at 0.5 um) is resolved, only the grid's steps are too coarse for the model.
constexpr double kUnresolvedScale = 10;

// Below this slope (mm per mm) every line through a point runs along its surface.
constexpr double kFlatSlope = 0.1;

// Some model of point i's neighbours, fitted without i, describes its window and predicts i's four
// nearest neighbours within the bound k sqrt(sigma^2 (1 + gain) + scale^2): the whole window or the
// wider one (a cubic, or the envelope of two across a crease; without every `condemned` point), an
// axis half-plane's plane or a diagonal half-plane's quadratic, a line through the point or a line
// from one side along the surface (without the points `in_groups` marks).
// Why not a quadratic on an axis half-plane or a line across the slope: on a 5 x 5 window an axis
// half-plane spans three rows, and its quadratic puts any three heights on a curve; at a sphere's foot
// it passed through the plate and the ring of steep points above it, and condemned the ring. A line
// from one side across the slope may be the other surface's (the plate beside the ring).
bool surface_resolved(const std::vector<Point3>& points, const std::vector<size_t>& hood, const std::vector<size_t>& wide,
                      const LineSides& sides, size_t i, const std::vector<double>& reference,
                      const std::vector<char>& condemned, const std::vector<char>& in_groups, double sigma, double k);

}  // namespace dg::host::lts
