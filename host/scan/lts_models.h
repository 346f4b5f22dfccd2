// The LTS filter's local models of a point's neighbours, each fitted without the point itself: a
// robust polynomial over a window and a quadratic along a line.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "host/geometry/point3.h"
#include "host/scan/local_polynomial.h"
#include "host/scan/lts_grid.h"

namespace dg::host::lts {

// The largest extrapolation gain a line may have and still vouch: 4.6 for five points at 1..5
// steps, 7.75 for four at 1..4, 15.8 for five from the second step on.
constexpr double kLineGainMax = 8;
// A line model uses the first kLinePoints neighbours on its side that are not suspected outliers.
constexpr int kLinePoints = 5;

// A window's point ranked by its |residual|, ties to the lower point number as a std::pair of the
// two ranks them, with its place in the window: a subset of a window of up to 64 points is then a
// mask, and a concentration step that keeps the points it was fitted to, or a start subset that
// is the last one again, is seen without sorting or searching the sets.
struct Ranked {
  double residual;
  size_t index;
  unsigned position;
  bool operator<(const Ranked& other) const {
    return residual < other.residual || (!(other.residual < residual) && index < other.index);
  }
};

// Sets entry m of `ranked`, sized beforehand, field by field. An entry built on the stack and pushed
// was copied in as 16-byte words whose load the 8-byte stores just before could not forward, and
// that stall was a sixth of the filter's iterations.
inline void set_ranked(std::vector<Ranked>& ranked, size_t m, double residual, size_t index) {
  Ranked& r = ranked[m];
  r.residual = residual;
  r.index = index;
  r.position = static_cast<unsigned>(m);
}

// Whether the places in `mask` hold exactly the `ranked` entries smallest in rank, `ranked` being
// one entry a place in place order: the largest inside ranks below the smallest outside. A
// concentration step whose fit keeps its own subset has converged, and this tells it without a
// selection (nth_element's mispredicted branches were a fifth of the filter's time).
inline bool keeps_mask(const std::vector<Ranked>& ranked, uint64_t mask) {
  const Ranked* largest_in = nullptr;
  const Ranked* smallest_out = nullptr;
  for (const Ranked& r : ranked) {
    if (mask >> r.position & 1) {
      if (!largest_in || *largest_in < r) largest_in = &r;
    } else if (!smallest_out || r < *smallest_out) {
      smallest_out = &r;
    }
  }
  return !largest_in || !smallest_out || *largest_in < *smallest_out;
}

// What the judges read of a model of point i's neighbours fitted without i: a window's robust
// model (LooModel) or a line's quadratic. Every point's test keeps up to seventeen of these
// (PointModels, lts_judges.h), so the window's polynomial itself is not among them (with it a test
// took 3.5 kB a point, 350 MB for 100,000 points).
struct LooFit {
  double prediction = 0;  // the model's height at point i
  double scale = 0;       // its trimmed residual scale
  // The largest |residual| to the model among point i's four nearest neighbours in the window.
  double near_worst = HUGE_VAL;
  // The prediction's variance in units of the noise variance: the line's extrapolation gain, and
  // for a window's model [(X^T X)^-1]_00 of its trimmed subset (the verdict bounds a window by its
  // scale instead; the split judge, whose point lies at its side's edge, uses it).
  double gain = 0;
  int dof = 1;  // the trimmed residuals' degrees of freedom, h - p (at least 1)
  // How many of those four neighbours the model kept: a model that trims them describes another
  // surface than the one i is on (across a crease from it). One byte, beside `ok`: the fit is
  // 40 bytes instead of 48 (up to seventeen a point).
  int8_t near_kept = 0;
  bool ok = false;
  // A line's quadratic, not the straight line that stands in for it: its prediction carries the
  // curvature it extrapolates, and with it the shape error the quadratic leaves (lts::vouches).
  bool curved = false;
};

// A window's model whose slope at the point is this steep or steeper (27 degrees) is fitted again
// in the frame of its tangent plane there (fit_tilted_polynomial), from the subset it kept, and
// that model is kept where its trimmed scale is under kTiltKeep times the upright one's and it
// predicts three of the point's four nearest neighbours within kTiltNearWithin times that scale.
// On the reference sphere's flank a quadratic in x and y leaves a shape error of 0.03 to 0.4 mm 9
// to 12.5 mm from its axis (5 x 5 window at 1 mm), beyond any outlier of a few micrometres of
// noise, and the point was listed as not judged; in its tangent plane 0.004 to 0.01 mm. The
// neighbours' condition keeps a model of the plate that leans over a ball's foot from passing for
// the ball's flank (ball plate at 5 um, seeds 1 to 6: false alarms 15 -> 9, worst precision 0.948
// -> 0.968). Keeping any tilted model of smaller scale let two outliers pass unlisted over seeds 1
// to 14, where halving it lets none. Its surface must have a height above the point and above
// those neighbours (LocalPolynomial::height). With four Newton steps, as before, heights unsettled
// by more than 100 nm were read: refusing those models listed 28 more clean points over seeds 1 to
// 14, seven parts and five noise levels. With eight steps, refusing the unsettled ones lists 5 more
// (11,158 -> 11,163); against four steps unchecked, false alarms went 94 -> 98 (the sphere 4 -> 8)
// and clean points listed 11,180 -> 11,163, none passed unlisted.
constexpr double kTiltSlope = 0.5;
constexpr double kTiltKeep = 0.5;
constexpr double kTiltNearWithin = 5;

// A robust local model fitted without point i: least trimmed squares by concentration steps from
// two starts, the h neighbours nearest to the filter's reference and the h nearest to the window's
// median height, the smaller trimmed scale kept. h is 70 % of the window (at least the maximal
// breakdown [n/2] + [(p+1)/2]): two or three outliers in one window stay out, and the trimmed
// scale stays a usable measure of how well the model describes the rest.
struct LooModel : LooFit {
  LocalPolynomial polynomial;  // the model itself (a window's; a constant as a flat plane)
};

// How far a model's prediction may miss a clean point: k times the prediction's standard error,
// the scan's noise amplified by the model's gain, with the model's own trimmed scale added for the
// shape it leaves undescribed.
inline double prediction_bound(double k, double sigma, double gain, double scale) {
  return k * std::sqrt(sigma * sigma * (1 + gain) + scale * scale);
}

// A quadratic in the distance along a line through the points on one side of point i,
// extrapolated to i; ok only with at least four points (one degree of freedom left to measure
// how well the quadratic describes them) and a gain of at most kLineGainMax. Where the scan's noise
// `sigma` explains the quadratic term (|c| within two standard errors), a straight line stands in:
// on a flat sliver whose nearest neighbour is an outlier, the quadratic through the next five
// points extrapolates with a gain of 15.8 and may not vouch, the straight line with 1.8.
LooFit line_model(const std::vector<Point3>& points, const LineSide& reach, size_t i, const std::vector<char>& suspect,
                  double sigma);

// A quadratic along a row, column or diagonal through point i, from up to kThroughLineSide
// neighbours on each side that are not suspected (at least two each): an interpolation, with a
// gain near 0.5. Where outliers crowd the windows (two side by side on a steep flank), each window
// holding them bends towards them, while the line without them still follows the surface on both
// sides of the point. `dof` holds n - 3.
constexpr int kThroughLineSide = 3;
// A line through a point judges with at least this many degrees of freedom left to its quadratic.
constexpr int kThroughLineDof = 3;
LooFit through_line_model(const std::vector<Point3>& points, const LineSide& before, const LineSide& after, size_t i,
                          const std::vector<char>& suspect);

// The window's points other than i and those `excluded` marks.
std::vector<size_t> others_in(IndexSpan window, size_t i, const std::vector<char>& excluded);

// Up to four of `members`, the nearest to point i in XY, nearest first (ties to the lower number).
std::vector<size_t> nearest_four(const std::vector<Point3>& points, const std::vector<size_t>& members, size_t i);
// The same into `out`, returning how many, with the caller's `scratch` for the ranking.
size_t nearest_four(const std::vector<Point3>& points, const std::vector<size_t>& members, size_t i, size_t (&out)[4],
                    std::vector<std::pair<double, size_t>>& scratch);

// Which of a window's points its model misses, for the whole window's model only (kept apart from
// the LooFit, of which every point holds up to seventeen): the judge may pass over a suspected
// neighbour, but not a surface beyond a crease. Point numbers are 32-bit, as in the windows
// (lts_grid.h).
struct WindowMisses {
  uint32_t near_index[4] = {};  // point i's four nearest neighbours in the window
  double near_residual[4] = {};  // and their |residuals|
  static constexpr int kWorst = 5;
  uint32_t worst_index[kWorst] = {};  // the window's points with the largest |residuals|, largest first
  double worst_residual[kWorst] = {};
};

// A window's robust model (see LooModel) of at most `max_order`, keeping `keep` of its points;
// `misses`, for the whole window, receives which of its points the model misses. With
// `tilt_on_slopes`, a quadratic or cubic on a slope of kTiltSlope or more is tried in its tangent
// plane's frame too.
LooModel loo_model(const std::vector<Point3>& points, const std::vector<size_t>& window, size_t i,
                   const std::vector<double>& reference, int max_order, double keep = 0.7,
                   WindowMisses* misses = nullptr, bool tilt_on_slopes = false);

}  // namespace dg::host::lts
