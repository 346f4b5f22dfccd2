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

// A point is asked whether the grid resolves its surface only where its own whole window misses its
// points by more than this many sigmas (or, for a point the judges passed, where none of its
// windows describes its points): a curved part that a cubic follows a little worse than the noise (the
// canister's dish at 0.5 um) is resolved, only the grid's steps are too coarse for the model.
// Five, not ten: the ball plate's balls rise 0.6 mm in their first grid step from the plate, and
// at their feet whole windows missed by 5 to 10 sigmas (over six seeds and five noise levels, false
// alarms on the ball plate 413 -> 384 and on the sphere 489 -> 439; 12 and 9 more outliers left
// unjudged; the four benchmark parts over 14 seeds unchanged).
constexpr double kUnresolvedScale = 5;

// Where the whole window misses its points by more than this many sigmas, the surface changes by
// hundreds of noise sigmas within a grid step, which the grid does not resolve: a point whose height
// lies between its neighbours' along all four lines through it is a point of that slope, not a
// spike, and is not judged. At the sphere's foot (a 6 mm fall in one step) such points were
// condemned. At 200: false alarms on the sphere 439 -> 271 and the ball plate 384 -> 368 (14 and 3
// more outliers unjudged); at 100 four outliers on the dome's steep rim at 0.5 um were taken for
// slope points, at 200 none.
constexpr double kSlopeScale = 200;
// The same where the window misses its points by more than this part of the grid step, whatever
// the noise: the surface bends more within a step than a cubic over the window follows (at 10 um
// of noise 200 sigmas are 2 mm, more than the sphere's foot misses by). At a tenth: false alarms on
// the sphere 271 -> 156, on the ball plate 368 -> 285 (19 and 3 more outliers unjudged); the
// dome's rim misses its windows by 0.05 mm at most and loses nothing (at a twentieth, 14).
constexpr double kSlopeStepFraction = 0.1;

// A one-sided line that rises more than this (mm per mm) to the point does not say the surface is
// resolved: along the level direction of a slope steeper still it is no level line, and at the
// sphere's foot such a line (a row across the flank) described its points and missed the next one
// (false alarms on the sphere over six seeds and five noise levels 640 -> 489, 17 more outliers
// unjudged; the step gauge's level lines beside its steps rise by nothing and still judge).
constexpr double kLineRiseMax = 0.5;

// Point i lies between its nearest neighbours along each of the four lines through it, and on each
// line they differ by more than the slope scale (kSlopeScale sigmas or kSlopeStepFraction of the
// grid step, the smaller): the surface falls steeply in every direction across the point, as on a
// ball's flank beside its foot, where the grid does not resolve it whatever its window says (at 10
// um of noise a window of the plate with the ball's first ring of points missed them by less than
// five sigmas and predicted the plate, 1.2 mm below them). Asked only where the point's whole window
// misses even its nearest neighbours by more than that scale (`window_near_worst_mm`). With
// `marked` given, a line whose nearest neighbour on one side is marked may pass with the next
// point on that side instead (an outlier beside a slope point).
bool on_unresolved_slope(const std::vector<Point3>& points, const LineSides& sides, size_t i,
                         const std::vector<char>& in_groups, double window_near_worst_mm, double sigma,
                         const std::vector<char>* marked = nullptr);

// A point the judges passed that lies far below a straight run of its line's points spanning it:
// kPitRunSide points on one side (the first not `marked` among the nearest kPitRunReach) and the
// nearest unmarked one of the first two on the other lie on one straight line within the
// noise (trimmed of nothing: a scale within 2 sigma), and the point lies below that line by more
// than kPitWiden times its bound k sqrt(sigma^2 (1 + gain) + scale^2) (or `limit_mm`, the larger).
// Only a pit narrower than two grid steps puts a real point there, which the grid does not
// resolve, so the point is listed, not passed. At the scan's edge beside the dome's rim the base
// plate is a strip one point wide, and outliers 44 to 84 sigma below it that lay near the cap's
// surface continued past its rim were vouched for by the cap's windows and passed unlisted (over
// 14 seeds and five noise levels three on the dome and one at the step gauge's edge; no clean point
// listed more but one on the dome at 10 um). Below only: the same run above a point is a real
// corner's tip where a diagonal cuts a block's corner (the step gauge's, 30 clean points listed).
constexpr int kPitRunSide = 3;
constexpr size_t kPitRunReach = 5;
constexpr double kPitWiden = 3;
bool below_a_straight_run(const std::vector<Point3>& points, const LineSides& sides, size_t i,
                          const std::vector<char>& marked, double sigma, double k, double limit_mm);

// Below this slope (mm per mm) every line through a point runs along its surface.
constexpr double kFlatSlope = 0.1;

// Some model of point i's neighbours, fitted without i, describes its window and predicts i's four
// nearest neighbours within the bound k sqrt(sigma^2 (1 + gain) + scale^2): the whole window or the
// wider one (a cubic, or the envelope of two across a crease; without every `condemned` point), an
// axis half-plane's plane or a diagonal half-plane's quadratic that also predicts the point's grid
// neighbours on its side, a line through the point or a line from one side along the surface, not
// one that climbs a slope through the point (without the points `in_groups` marks); and i is no
// point of a slope steeper than the grid resolves (kSlopeScale, on_unresolved_slope). A condemned point on
// such a slope is judged only by models of its own surface: a half-plane that misses it by more
// than the slope scale vouches only where another half-plane's level lies beyond that scale on its
// other side (a step's two levels), and an envelope only where it predicts all eight of the
// point's grid neighbours. `clears`, when given, says whether one of the window's cubics, crease
// envelopes or half-planes that vouch also predicts i within its bound (the search going on past
// those that miss it); `predicts`, when given, whether one of the models that describe it,
// whichever, predicts i within its own bound (with the gain of its extrapolation to i) or
// `limit_mm`, the larger: the search then goes on past a model that describes the window and
// misses i.
// Why not a quadratic on an axis half-plane or a line across the slope: on a 5 x 5 window an axis
// half-plane spans three rows, and its quadratic puts any three heights on a curve; at a sphere's foot
// it passed through the plate and the ring of steep points above it, and condemned the ring. For the
// same reason a half-plane's model describes only with the points it fits spanning more columns and
// rows than its order needs (a diagonal half-plane's trimmed quadratic kept three rows: 709 -> 640
// false alarms on the sphere over six seeds and five noise levels, no outlier lost). A line from one
// side across the slope may be the other surface's (the plate beside the ring).
bool surface_resolved(const std::vector<Point3>& points, IndexSpan hood, IndexSpan wide,
                      const LineSides& sides, size_t i, const std::vector<double>& reference,
                      const std::vector<char>& condemned, const std::vector<char>& in_groups, double sigma, double k,
                      bool* clears = nullptr, bool* predicts = nullptr, double limit_mm = 0);

}  // namespace dg::host::lts
