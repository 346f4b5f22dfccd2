// Estimating the measurement noise of a scan from the data alone, so that a fit stops at it.
#pragma once
#include <vector>

#include "host/fit/parameterize.h"
#include "host/scan/point_reader.h"

namespace dg::host {

struct NoiseEstimate {
  double sigma_mm = 0;          // the gauge's noise, with the reading step's share taken out
  double reading_sigma_mm = 0;  // the scatter of the readings: noise and rounding to the step together,
                                // never below the reading step / sqrt(12)
  double resolution_mm = 0;     // the reading step (from the file, or found in the values); 0 none
};

// The noise along the probe direction (z); zeros when it cannot be told.
// With scan lines: third differences of successive, evenly spaced points along each line, whose
// smooth part is of the order of spacing^3 * z''' and whose noise part has variance 20 sigma^2.
// Their spread is a truncated RMS (values past 3 sigma dropped, iterated from the median and
// corrected for the truncation), so an edge or outlier does not inflate it and, unlike a median,
// it is not quantized by the reading step. Without lines: quadratics fitted to small XY cells,
// the median of their residual deviations. Readings rounded to a step q carry a rounding error of
// variance q^2 / 12 (Sheppard's correction), which `sigma_mm` leaves out and `reading_sigma_mm`
// keeps: a fit's residuals contain it.
NoiseEstimate estimate_gauge_noise(const PointCloud& cloud, const Parameters& params);
// estimate_gauge_noise(...).sigma_mm.
double estimate_noise(const PointCloud& cloud, const Parameters& params);

}  // namespace dg::host
