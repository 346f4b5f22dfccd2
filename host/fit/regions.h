// Creases and steps as region boundaries: a scan split into smooth regions, each fitted within the
// tolerance, and each surface trimmed where it meets its neighbour (Koivunen and Bajcsy 1992,
// sections 5.3 and 6: characterize, segment at discontinuities, fit each piece).
#pragma once
#include <string>
#include <vector>

#include "host/fit/tolerance_fit.h"
#include "host/geometry/trimmed_face.h"
#include "host/scan/point_reader.h"

namespace dg::host {

struct RegionOptions {
  ToleranceOptions tolerance;  // for each region's fit
  // Points in each local quadratic: small, so a window fits between a crease and the scan's edge
  // (the dome's base plate shows only in the scan's corners).
  int neighbours = 12;
  size_t min_region_points = 12;
};

struct RegionReport {
  size_t core_points = 0;    // smooth points that seeded it
  size_t points = 0;         // points it was fitted to
  bool kept = false;
  std::string reason;        // the region's own refusal
  FitValidation validation;
  // The extrapolation to the trim: the points beside another region or a crease, predicted by the
  // region's net fitted without them.
  size_t boundary_points = 0;
  double boundary_max_mm = 0;
};

struct RegionFit {
  int regions = 0;  // smooth regions found; below 2 nothing else is filled in
  std::vector<TrimmedFace> faces;
  std::vector<RegionReport> reports;  // per region
  std::vector<int> face_region;       // per face, its region
  size_t crease_points = 0;           // points within no smooth window (on or beside a crease or step)
  size_t unassigned_points = 0;       // points no region's surface passes within the tolerance
  bool kept = false;
  std::string reason;                 // why not, when not kept
  double max_distance_mm = 0;         // every point to the face above it
  std::vector<double> distances;      // per point, signed, to the face above it
  FitValidation validation;           // the regions' checks between the samples, summed
  double noise_sigma_mm = 0;
};

// Segments a table-XY scan: a neighbourhood of 12 points that a quadratic fits to within three
// noise sigmas RMS (or a quarter of the tolerance) is smooth, and points joined through smooth
// neighbourhoods form a region;
// the points between regions are the creases and steps. Each region is fitted with
// fit_to_tolerance over its own box (control points beyond its points placed, not fitted), the
// crease points join the region whose surface passes nearest (within the tolerance), and the
// regions are fitted again. Where two surfaces cross the boundary is their intersection, else
// (a step) the line midway between their points. Kept when every region kept the tolerance and
// passed its validation between the samples, predicts its own outermost points within the
// tolerance when fitted without them (the surface is extrapolated from them to the trim), and
// every point lies within the tolerance of the face above it. Fewer than two regions: `regions` says so and the caller fits one surface.
RegionFit fit_regions(const PointCloud& cloud, const std::vector<double>* weights, const RegionOptions& options);

}  // namespace dg::host
