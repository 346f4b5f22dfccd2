// One B-spline surface over a whole table-XY scan, to a tolerance: the creases found in the data
// as knots, the tolerance loop and its validation between the samples (fit --tolerance --no-regions).
#pragma once
#include <vector>

#include "host/fit/crease_detect.h"
#include "host/fit/tolerance_fit.h"
#include "host/scan/point_reader.h"

namespace dg::host {

// As `digitizer fit --tolerance T --no-regions` fits: weights from the points' sigma, knots of
// multiplicity 3 at the creases detect_creases finds (returned in *creases with the parameters), a
// bicubic net refined until it keeps the tolerance. A fit that cannot start (a crease's knots with
// too few lines about them), or sigmas that cannot weight a fit (sigma_weights.h), comes back refused with the
// reason instead of throwing.
ToleranceResult fit_one_surface(const PointCloud& cloud, double tolerance_mm, Parameters* params, Creases* creases);

}  // namespace dg::host
