// The standard uncertainty of a surface that a method without a closed-form covariance fitted
// (inverse progressive search, Hermite interpolation): the Monte Carlo method of GUM Supplement 1.
#pragma once
#include <functional>
#include <vector>

#include "host/geometry/bspline_surface.h"
#include "host/geometry/surface_uncertainty.h"

namespace dg::host {

struct ReplicaPlan {
  int replicas = 200;
  unsigned seed = 1;
  int grid = 21;  // nodes per direction over the surface's parameter domain
};

// Refits `replicas` copies of `points`, each z moved by normal noise of its point's `sigma_mm`
// (the gauge reads along z), with `refit`, and takes the spread of the surface's position along
// the nominal's normal at each grid node: u(u, v). The replicas run on every core; replica k's
// noise depends on the seed and k only, so the result does not depend on the machine. A replica
// the method refuses (it throws) counts against none and is reported in `refused` (more than a
// tenth refused: not computed). sigma_mm, max_mm, mean_mm are set; sigma_from says "Monte Carlo".
SurfaceUncertainty replica_uncertainty(const std::vector<Point3>& points, const std::vector<double>& sigma_mm,
                                       const BSplineSurface& nominal,
                                       const std::function<BSplineSurface(const std::vector<Point3>&)>& refit,
                                       const ReplicaPlan& plan, int* refused = nullptr);

}  // namespace dg::host
