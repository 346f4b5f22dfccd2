// The standard uncertainty of a fitted surface's height over its parameter domain, as a small grid.
#pragma once
#include <string>
#include <vector>

namespace dg::host {

// The standard uncertainty of a fitted surface's height (or normal position) on a grid over its
// parameter domain, from the coefficients' covariance: u(x, y); U = 2u is the expanded uncertainty.
struct SurfaceUncertainty {
  bool computed = false;
  double sigma_mm = 0;     // the point standard uncertainty it was propagated from
  std::string sigma_from;  // where that came from: "sigma column", "noise estimate", ...
  int rows = 0, cols = 0;  // grid over [0, 1]^2 in (u, v); u_mm[r * cols + c] at u = c/(cols-1), v = r/(rows-1)
  // For a trimmed face, a node outside the face holds kOffFace (null in SURF.json) and enters
  // neither max nor mean.
  std::vector<double> u_mm;
  double max_mm = 0, mean_mm = 0;
};

// The value of a grid node that lies outside a trimmed face.
constexpr double kOffFace = -1.0;

// True when `u` holds a grid to interpolate.
bool has_uncertainty_grid(const SurfaceUncertainty& u);

// u at (a, b) in [0, 1]^2 of the parameter domain by bilinear interpolation between the grid's
// nodes, over those of the four that lie on the face (renormalized); false when none does.
bool uncertainty_at(const SurfaceUncertainty& u, double a, double b, double& value);

}  // namespace dg::host
