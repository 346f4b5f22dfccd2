// The algebraic sphere fit: linear in the centre and one more unknown, so it needs no start.
#include "host/scan/sphere_fit.h"

#include <cmath>

#include "host/scan/small_solve.h"

namespace dg::host {

bool fit_sphere_algebraic(const std::vector<Point3>& cap, const Point3& origin, Point3& centre, double& radius) {
  double n[4][4] = {}, rhs[4] = {};
  for (const Point3& p : cap) {
    const double x = p.x - origin.x, y = p.y - origin.y, z = p.z - origin.z;
    const double row[4] = {2 * x, 2 * y, 2 * z, 1};
    const double w = x * x + y * y + z * z;
    for (int i = 0; i < 4; ++i) {
      rhs[i] += row[i] * w;
      for (int j = 0; j < 4; ++j) n[i][j] += row[i] * row[j];
    }
  }
  double s[4];
  if (!solve_small(4, n, rhs, s)) return false;
  centre = {s[0] + origin.x, s[1] + origin.y, s[2] + origin.z};
  radius = std::sqrt(std::fmax(0.0, s[3] + s[0] * s[0] + s[1] * s[1] + s[2] * s[2]));
  return std::isfinite(centre.x) && std::isfinite(centre.y) && std::isfinite(centre.z) && std::isfinite(radius);
}

}  // namespace dg::host
