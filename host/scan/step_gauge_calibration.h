// The gauge's scale measured on a step gauge: the heights of its steps' tops, read, against their
// certified heights.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "host/scan/point_reader.h"
#include "host/scan/table_calibration.h"

namespace dg::host {

struct StepLevel {
  double x_mm = 0, y_mm = 0;  // the centre of the step's top
  double height_mm = 0;  // its top's mean reading less the plate's beside it, edges left out
  double u_mm = 0;       // its standard uncertainty: the readings' scatter and the map's
  size_t points = 0;
};

struct GaugeScale {
  // The gauge reads (1 + scale) times its travel: a reading z is z / (1 + scale) long.
  double scale_ppm = 0, u_scale_ppm = 0;  // standard uncertainty (k = 1)
  double residual_rms_mm = 0;              // of the steps' heights about the fitted line
  std::vector<StepLevel> steps;            // in the certificate's order
};

// `scan`: readings of the steps' tops and of the plate they stand on beside them (corrected by a
// calibration, or not), the steps in a row in any direction, the plate beside each. The readings
// fall into levels (sorted heights apart by more than 0.2 mm start a new level; a level needs 10
// readings, fewer are a wall's): the lowest is the plate, the others the steps, matched to
// `certified` (their heights, mm, from any one datum, at least 0.5 mm apart) by height order.
// Each step's height is its top's mean less the plate's mean beside it over the same span along
// the row, both from readings more than 0.7 mm inside the top's edges: a tilt of the table's
// travel along the steps then cancels, where tops alone would read it as scale (3 x 85 urad =
// 256 ppm on a typical table). Each height's u is the readings' scatter over their counts and
// `map`'s node uncertainty at the top and at the plate, when given. In the certificate's order.
// Throws CalibrationError, saying why, when the levels do not match the plate and the steps one
// for one or a step has no plate beside it.
std::vector<StepLevel> measure_steps(const PointCloud& scan, const std::vector<double>& certified, const std::string& name,
                                     const TableCalibration* map = nullptr);

// The steps as measure_steps finds them; their heights then fit h = a + (1 + scale) H by weighted
// least squares. Throws as measure_steps does, and when the steps span less than 1 mm or the
// scale comes out beyond 2 %.
GaugeScale calibrate_gauge_scale(const PointCloud& scan, const std::vector<double>& certified, const std::string& name,
                                 const TableCalibration* map = nullptr);

// The certificate: one height in mm per line (a header line allowed). Throws CalibrationError.
std::vector<double> read_step_certificate(const std::string& path);

}  // namespace dg::host
