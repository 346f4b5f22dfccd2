// Closest points on a surface for points with no parameters of their own (inspection): a sampled
// start found through a spatial grid, then Gauss-Newton, so the search cannot settle on a local
// minimum on the wrong side of a patch.
#pragma once
#include <vector>

#include "host/geometry/closest_point.h"

namespace dg::host {

class SurfaceLocator {
 public:
  // Samples `per_span` x `per_span` points in every knot cell (at most 512 per direction).
  explicit SurfaceLocator(const BSplineSurface& surface, int per_span = 4);

  // The closest surface point to p: Gauss-Newton from the nearest sample and from the nearest
  // sample of a different region when one is about as near, keeping the better.
  Closest closest(const Point3& p) const;
  const BSplineSurface& surface() const { return surface_; }

  struct Sample {
    Point3 point;
    double u, v;
  };
  // The Gauss-Newton starts closest() uses for p: the nearest sample, and the second one (the
  // nearest sample more than two sample spacings away in parameters and within 1.5 times the
  // nearest's distance; samples().size() when there is none).
  struct Starts {
    size_t nearest, second;
  };
  Starts starts(const Point3& p) const;
  const std::vector<Sample>& samples() const { return samples_; }

 private:
  long cell_key(int x, int y, int z) const;
  void cell_of(const Point3& p, int& x, int& y, int& z) const;

  const BSplineSurface& surface_;
  PatchForm form_;  // the surface in power form, for the many projections an inspection makes
  std::vector<Sample> samples_;
  Point3 origin_;
  double cell_mm_ = 1;
  int nx_ = 1, ny_ = 1, nz_ = 1;
  std::vector<size_t> first_;   // bucket b holds samples_[first_[b] .. first_[b + 1]) (samples in bucket order)
  double spacing_u_ = 0, spacing_v_ = 0;
};

}  // namespace dg::host
