// Reading a B-spline surface from a STEP file (ISO 10303-21): a nominal surface to inspect against.
#pragma once
#include <stdexcept>
#include <string>

#include "host/geometry/bspline_surface.h"

namespace dg::host {

class StepError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The first B_SPLINE_SURFACE_WITH_KNOTS of the DATA section, in millimetres (the file's length
// unit applied: SI metres with any prefix, or inches). Polynomial surfaces only: a rational one
// with unequal weights is refused. Malformed text, a reference to a missing instance, counts that
// disagree or numbers that are not finite are errors naming the file and the instance.
BSplineSurface parse_step_surface(const std::string& text, const std::string& name);
BSplineSurface read_step_surface(const std::string& path);

}  // namespace dg::host
