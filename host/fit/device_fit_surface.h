// The device's fitted surface (a FitResult) as a surface file: heights over the scanned rectangle.
#pragma once
#include <string>

#include "digitizer.pb.h"
#include "host/geometry/fitted_surface.h"

namespace dg::host {

// A height field in mm: control points at the Greville abscissae of the rectangle, z from the
// device. The Bezier patch has knots 0,0,0,0,1,1,1,1; the net the uniform knots (i - 3) / (side - 3)
// the device fitted with. Throws FitError for a result that is not FIT_OK (saying why) or that is
// malformed (counts that disagree, an empty rectangle).
FittedSurface surface_from_device_fit(const digitizer_FitResult& fit, const std::string& source);

}  // namespace dg::host
