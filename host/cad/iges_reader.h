// Reading a B-spline surface (entity 128) from an IGES file: a nominal surface to inspect against.
#pragma once
#include <stdexcept>
#include <string>

#include "host/geometry/bspline_surface.h"

namespace dg::host {

class IgesError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The first entity 128 of the file, in millimetres (the global section's unit and scale applied).
// Polynomial surfaces only: unequal weights (a rational surface) are refused, as is anything
// malformed: a line outside the fixed-column layout, a directory entry pointing nowhere, counts that
// disagree with the data, a number that is not one or not finite. Messages name the file and the
// section line.
BSplineSurface parse_iges_surface(const std::string& text, const std::string& name);
BSplineSurface read_iges_surface(const std::string& path);

}  // namespace dg::host
