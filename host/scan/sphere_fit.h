// A sphere through points, for ball centres and the start of the gauge tilt's fit.
#pragma once
#include <vector>

#include "host/geometry/trimmed_face.h"

namespace dg::host {

// The algebraic least-squares sphere: x^2 + y^2 + z^2 = 2 a x + 2 b y + 2 c z + d in coordinates
// relative to `origin` (for conditioning; a point near the data), centre (a, b, c) + origin.
// It minimizes a weighted distance, not the geometric one, so it starts a geometric fit or serves
// where the points cover a cap evenly. False when the points do not determine a sphere.
bool fit_sphere_algebraic(const std::vector<Point3>& points, const Point3& origin, Point3& centre, double& radius);

}  // namespace dg::host
