// The gauge's tilt measured on a reference sphere: a leaning plunger shears every scan (a reading r
// high touches the part r times the lean off to the side), which a sphere of certified diameter shows.
#pragma once
#include <cstddef>
#include <string>

#include "host/scan/point_reader.h"
#include "host/scan/table_calibration.h"

namespace dg::host {

struct GaugeTilt {
  // The plunger's axis leans towards +x and +y by these angles: a point read r high lies at
  // (x + r sin(tilt_x), y + r sin(tilt_y)) and r cos(tilt) high.
  double tilt_x_urad = 0, tilt_y_urad = 0;
  double u_tilt_x_urad = 0, u_tilt_y_urad = 0;  // standard uncertainties (k = 1), all of the below
  // Their parts: the readings' scatter about the fit, and the map's uncertainty under the sphere
  // (a slope of the map's error there shapes the cap as a lean does).
  double u_noise_x_urad = 0, u_noise_y_urad = 0, u_map_x_urad = 0, u_map_y_urad = 0;
  double centre_mm[3] = {};   // the sphere's fitted centre (corrected coordinates)
  double free_diameter_mm = 0;  // what the readings give alone (an algebraic fit; the check on the certificate)
  double residual_rms_mm = 0;   // of the readings' distances from the fitted sphere
  size_t points = 0;            // readings on the cap that were fitted
  LeadError lead;               // the screws' periodic error, when a lead was given
};

// How far from the sphere's top, sideways, the readings the fit uses reach (the cap within 55
// degrees of the top): what a scan of the sphere must cover around it.
double sphere_cap_reach_mm(double diameter_mm);

// `scan`: a sphere of certified `diameter_mm` scanned from above, its readings corrected by the
// table's map and axes already. The cap within 55 degrees of the sphere's top (the highest reading)
// is fitted by least squares on the geometric distance: centre and the two tilt components, the
// radius held at the certificate's, by Gauss-Newton from an algebraic sphere. Throws
// CalibrationError, saying why, when the readings hold no such sphere, too few of them lie on its
// cap, the diameter they give disagrees with the certificate by more than 2 %, or the fit's RMS
// exceeds 10 um (a dirty ball, another diameter, a slipping stand).
// `map`, when the readings were corrected by a travel map: its nodes' uncertainties are carried
// into the tilt's by the fit's sensitivity to each node (GUM 5.1.2, the nodes taken as independent).
// `lead_mm` > 0: the screws' periodic error is fitted too, one turn of that lead on each axis (a
// sine and a cosine each, four unknowns more), from where the flanks' slope shows a sideways shift.
GaugeTilt calibrate_gauge_tilt(const PointCloud& scan, double diameter_mm, const std::string& name,
                               const TableCalibration* map = nullptr, double lead_mm = 0);

}  // namespace dg::host
