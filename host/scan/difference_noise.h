// The noise of evenly spaced sequences of points (scan lines, grid rows and columns) from their
// fifth differences, which cancel the part's shape up to a quartic.
#pragma once
#include <cstddef>
#include <vector>

#include "host/geometry/point3.h"

namespace dg::host {

// Differences of this order along a line cancel the part's shape up to a polynomial of one degree
// less; third differences left a bias of spacing^3 times the third derivative (18 % on the
// canister at 1 um of noise). Their noise has variance sum C(k, i)^2 sigma^2 = C(2k, k) sigma^2.
constexpr int kNoiseDifferenceOrder = 5;

// The standard deviation of z's noise over `sequences` (indices into points, in order along each).
// Only windows of six points spaced evenly in XY (within 10 %) count. Their differences' spread is
// a truncated RMS (values past 3 sigma dropped, iterated from the lower quartile, corrected for the
// truncation), after dropping every window within one window of a value past 3 sigma: a crease or
// a steep, curved edge shows as a run of large differences whose shoulders are still inflated
// (while at least a fifth of the windows remain; the truncated RMS of all of them otherwise).
// Unlike a median it is not quantized by the gauge's reading step. 0 with fewer than 8 windows.
double difference_noise_sigma(const std::vector<Point3>& points, const std::vector<std::vector<size_t>>& sequences);

// The standard deviation of zero-mean normal values among outliers (fewer than three quarters of
// them): the RMS of those within 3 s divided by the RMS a normal distribution has within 3 sigma,
// iterated from the lower quartile of |v| (a median breaks down where steps spoil most values).
double truncated_sigma(const std::vector<double>& values);

}  // namespace dg::host
