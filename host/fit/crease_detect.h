// Creases and steps that run across a scan, found from the data, so a fit can place multiple knots
// there (Koivunen and Bajcsy 1992, section 6: subdivision at discontinuities).
#pragma once
#include <vector>

#include "host/scan/point_reader.h"
#include "host/fit/parameterize.h"

namespace dg::host {

struct Creases {
  std::vector<double> u, v;  // parameter values for knots of multiplicity = degree (C0 there)
};

// Along each scan line (u), and for a table-XY height field also along each column of equal x (v),
// the slope between neighbours is compared: where it turns by more than 8 noise sigmas and by 4
// times the turning around it, the point is a crease candidate (a step gives two, one at each end
// of its ramp). A tensor-product B-spline can only break along a whole parameter line, so a
// position becomes a crease when candidates line up there on at least half of the lines; a crease
// that wanders across the part (the rim of a dome) is left to knot refinement. A cluster of
// candidates one sample wide gives a knot at each end, so the ramp between two samples of a step
// becomes a straight piece. Needs scan lines; without them there is nothing to align and the
// result is empty.
Creases detect_creases(const PointCloud& cloud, const Parameters& params, double noise_sigma_mm);

// `knots` (clamped) with `degree` copies of each crease parameter added, kept sorted.
std::vector<double> with_crease_knots(std::vector<double> knots, const std::vector<double>& creases, int degree);

}  // namespace dg::host
