// Estimating the measurement noise of a scan from the data alone, so that a fit stops at it.
#pragma once
#include "host/scan/point_reader.h"
#include "host/fit/parameterize.h"

namespace dg::host {

// The standard deviation of the noise along the probe direction (z), mm; 0 when it cannot be told.
// With scan lines: third differences of successive, evenly spaced points along each line, whose
// smooth part is of the order of spacing^3 * z''' and whose noise part has variance 20 sigma^2;
// taken robustly (median absolute value / 0.6745), so outliers and edges do not inflate it.
// Without lines: quadratics fitted to small XY cells, the median of their residual deviations.
double estimate_noise(const PointCloud& cloud, const Parameters& params);

}  // namespace dg::host
