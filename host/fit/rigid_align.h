// Rigid best-fit alignment of measured points to a nominal surface, as CMM software does before
// comparing: the rotation and translation that minimise the squared orthogonal distances.
#pragma once
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "host/geometry/surface_locator.h"

namespace dg::host {

struct RigidTransform {
  std::array<std::array<double, 3>, 3> rotation{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  Point3 translation;  // mm
  Point3 apply(const Point3& p) const;
  double angle_deg() const;  // the rotation's angle
};

struct Alignment {
  RigidTransform transform;  // measured -> nominal
  int iterations = 0;
  double rms_before_mm = 0, rms_after_mm = 0;  // over every point taking part, but those beyond the edge
  bool converged = false;
  size_t left_out = 0;  // points beyond 3 robust sigmas in the last step, left out of it
  // Points beyond the nominal's edge (beyond_edge) under the transform kept: their distance is to
  // the edge, not along a normal, so they are left out of the steps and the RMS (Turk and Levoy
  // 1994 leave out the pairs on a mesh's boundary for the same reason).
  size_t beyond_edge = 0;
  // Freedoms the nominal's shape does not fix (a plane's two slides and turn, a sphere's three
  // turns about its centre), held still in the last step rather than moved at random.
  int held = 0;
};

// Point-to-plane ICP (Chen and Medioni's linearisation): each step finds every point's closest
// nominal point and normal, solves the 6 x 6 least-squares problem for a small rotation and a
// translation over the points within 3 robust sigmas (a trimmed fit that outliers cannot pull)
// and over the nominal (a scan larger than a single face, or an open mesh, is aligned by its points
// over it: those beyond the edge would pull the part towards the edge),
// and applies it as an exact rotation. At most `max_points` points, evenly strided,
// take part. Stops when a step moves no point by more than 1e-7 mm, or after 50 steps.
// Any nominal whose closest points carry their normal: a surface, a mesh, a CAD part.
Alignment align_to_nominal(const std::vector<Point3>& points, const std::function<Closest(const Point3&)>& closest,
                           size_t max_points = 20000);
Alignment align_to_surface(const std::vector<Point3>& points, const SurfaceLocator& nominal, size_t max_points = 20000);

// The degrees of freedom a step may move, in the order rotation about x, y, z, translation along x,
// y, z.
using FreedomMask = std::array<bool, 6>;

// One datum of a datum alignment: the measured points of the region the user named, and what it
// fixes (the mask) with what was found.
struct DatumFit {
  std::string name;
  std::vector<Point3> points;  // measured, in the scan's coordinates
  FreedomMask fixes{};
  size_t used = 0;             // points that took part (at most 20,000, evenly strided)
  double rms_after_mm = 0;     // its points' RMS distance to the nominal once aligned
  std::string fixes_text;      // "tilt about x and y, height"
};

// A 3-2-1 datum alignment, as a drawing's datum reference frame: each datum in turn is fitted to
// the nominal with only the freedoms it fixes, the earlier ones held. One datum (A) fixes the
// tilts and the height (the part resting on a plane); two add, from B, the rotation about z and
// both translations in the table's plane; three split those, B fixing the rotation about z and x,
// C the translation along y. A height-only scan fixes x and y only where the datum's surface
// slopes: a datum whose points leave one of its freedoms undetermined (its mean squared
// sensitivity to that freedom, rotations taken over the points' own radius, below 1e-4: less than
// a 0.6 degree slope) throws std::invalid_argument naming the datum and the freedom; so does a
// datum whose points the later datums carry all beyond the nominal's edge (it has no RMS to give).
Alignment align_to_datums(std::vector<DatumFit>& datums, const std::function<Closest(const Point3&)>& closest);

}  // namespace dg::host
