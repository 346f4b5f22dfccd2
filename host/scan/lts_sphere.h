// A sphere's cap (or a plane) as a model of a point's neighbours, for the LTS judges where a ball bends
// or falls faster than a polynomial over the grid's window follows (a reference sphere's flank, a ball
// plate's balls) or a block's edge drops by millimetres.
#pragma once
#include <cmath>
#include <cstddef>
#include <vector>

#include "host/geometry/point3.h"
#include "host/scan/lts_grid.h"
#include "host/scan/lts_models.h"

namespace dg::host::lts {

// A sphere judges only with at least this many of its window's points kept: its four parameters
// leave eight degrees of freedom to measure how well it describes them.
constexpr int kSphereKeptMin = 12;
// Points within this many noise sigmas of the sphere (vertically) are its own; the rest (outliers,
// the plate beside a ball's foot) are left out of its fit.
constexpr double kSphereKeepSigmas = 4;
// Where the sphere falls this steeply at the point (56 degrees) or more, it judges keeping two of
// the point's four nearest neighbours, not three: beside a ball's foot the neighbours outwards
// and to one side lie on the plate (the sphere's ring 12 mm from its axis: over seeds 1 to 14 and
// five noise levels 95 more outliers caught, no false alarm more). On the dome's rim, 0.93 steep,
// a sphere keeping two neighbours condemned a real point at 10 um.
constexpr double kSphereSteepSlope = 1.5;
// A condemned point that a window describing its neighbours to the noise misses by this many
// times its bound is beyond a sphere's doubt (judge_on_spheres).
constexpr double kBeyondDoubt = 10;
// How an excluded point stands among the nearest four (sphere_model's `stand_in`): not at all (0),
// as a neighbour not kept, or by its replacement height.
constexpr char kNotKept = 1, kByHeight = 2;

// A sphere z = c + s sqrt(r^2 - (x - a)^2 - (y - b)^2) (s = +1 for a ball, -1 for a bowl) through
// point i's neighbours in `window`, without i and the `excluded`, fitted to their heights: the
// noise is in the gauge's reading, vertical, so the residuals are. Robust: least trimmed squares
// by concentration steps over half the points, from the spheres through 3 x 3 blocks of them
// (and, for a surface that is less than half of the window, from the blocks whose spheres come
// nearest the most points), then every point within kSphereKeepSigmas * `sigma_mm` kept and the
// sphere fitted to them again.
// As a LooFit: the prediction at i, the kept residuals' scale, the prediction's gain (its variance
// over sigma^2, from the fit's linearization), and how many of the four nearest neighbours were
// kept (`near_worst` stays HUGE_VAL, the worst case: the judges here do not read it). Not ok
// where fewer than kSphereKeptMin points are kept, the points determine no sphere of radius under
// 1 m, or i lies outside the sphere's outline. The nearest four are sought among the fitted
// points and the excluded ones that `stand_in` marks: kNotKept ones count as not kept, kByHeight
// ones as kept where the sphere passes within kSphereKeepSigmas * `sigma_mm` of their
// `replacement` heights.
struct SphereFit : LooFit {
  // The least height difference between point i and one of its four nearest neighbours that the
  // sphere did not keep (HUGE_VAL when it kept them all).
  double unkept_near_gap_mm = HUGE_VAL;
  double slope = 0;  // the sphere's steepest slope at point i (mm per mm)
};
SphereFit sphere_model(const std::vector<Point3>& points, IndexSpan window, size_t i, const std::vector<char>& excluded,
                    double sigma_mm, const std::vector<char>* stand_in = nullptr,
                    const std::vector<double>* replacement = nullptr);
// The same with a plane z = a + b x + c y for the sphere: the flat side of a window that crosses a
// cliff (the plate behind a step gauge's block, the base below the reference sphere's equator).
SphereFit plane_model(const std::vector<Point3>& points, IndexSpan window, size_t i, const std::vector<char>& excluded,
                      double sigma_mm, const std::vector<char>* stand_in = nullptr,
                      const std::vector<double>* replacement = nullptr);

// The points listed as not judged (`unjudged`, ascending) that a sphere through their wider window
// condemns leave the list: `condemned` is set and their `replacement` is the sphere's height. A
// sphere condemns where it describes its points to the noise (scale within 2 sigma), keeps three of
// the point's four nearest neighbours (two on a kSphereSteepSlope), extrapolates no further than a
// line may (gain up to kLineGainMax), puts the point beyond its bound and `limit_mm`, and no
// neighbour it left out lies nearer the point; in passes until one condemns none more, the points
// condemned by an earlier pass standing in among the nearest by their spheres' heights. Where no
// sphere may judge, a plane may, on the same terms but keeping three of the four nearest (the
// points the other judges condemned among them, by the heights those gave them), or two to
// condemn a point beside a cliff whose side it leaves out. Listed points off their models in twos
// to fours, each among another's nearest four, are then judged together on the hypothesis that
// all of them are off (each standing in for the others by its model's height), and condemned only
// if every one is; the passes follow once more if any were. A ball's flank falls by millimetres
// within a grid step and its top bends more than a cubic over the window follows: there the
// windows' polynomials could not tell an outlier from the surface. The sphere only condemns: a
// point it would clear stays listed, since at a crease a sphere continued past its edge can pass
// for the other surface (the dome's plate beside its rim at 10 um: two outliers cleared over
// fourteen seeds). Then a condemned point that such a sphere or plane (fitted without every
// condemned point) predicts within its bound is no longer condemned but listed: a real point on a
// ball's first ring that a judge following the ball worse condemned. Not asked of the points
// marked `beyond_doubt`: condemned by a window that describes their neighbours to the noise, at
// kBeyondDoubt times its bound or more.
void judge_on_spheres(const std::vector<Point3>& points, const WindowLists& wide, std::vector<char>& condemned,
                      const std::vector<char>& beyond_doubt, double sigma_mm, double outlier_sigmas, double limit_mm,
                      std::vector<double>& replacement, std::vector<size_t>& unjudged);

}  // namespace dg::host::lts
