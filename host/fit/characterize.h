// Surface characterization (Koivunen and Bajcsy 1992, section 5.3): local quadratic fits give derivatives, mean
// and Gaussian curvature; each point gets one of the eight HK surface types; connected points of
// one type form regions; the regions crossed along the scan suggest the control net's size.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "host/scan/point_reader.h"

namespace dg::host {

// Besl and Jain's labels by the signs of H and K (z up: a dome is a peak).
enum class SurfaceType : uint8_t { kPeak, kRidge, kSaddleRidge, kFlat, kMinimal, kPit, kValley, kSaddleValley };

const char* surface_type_name(SurfaceType type);

struct CharacterizeOptions {
  int neighbours = 25;       // points in each local quadratic fit (Koivunen and Bajcsy 1992: a 5 x 5 window)
  double zero_curvature = 0; // |H|, |K| (1/mm, 1/mm^2 as its square) below this count as zero; 0: from the noise
  bool robust = false;       // LTS-filter the heights first (Koivunen and Bajcsy 1992, section 5.2's scheme)
  size_t min_region = 5;     // smaller regions are reported but do not count towards the net
};

struct PointCharacter {
  double fx = 0, fy = 0, fxx = 0, fxy = 0, fyy = 0;  // derivatives of z(x, y)
  double mean_curvature = 0, gaussian_curvature = 0;  // 1/mm, 1/mm^2
  SurfaceType type = SurfaceType::kFlat;
  // False where the point's neighbours do not determine a quadratic (too few distinct rows or
  // columns among them, as on a scan of two lines): its derivatives and curvatures are zeros that
  // say nothing, it has no type (counted in `undetermined`, not in type_counts) and joins no region.
  bool determined = true;
  uint32_t region = 0;
};

struct Characterization {
  std::vector<PointCharacter> points;
  double zero_curvature = 0;                 // the threshold used, 1/mm
  size_t type_counts[8] = {};
  size_t undetermined = 0;                   // points whose neighbours determine no quadratic
  uint32_t regions = 0;                      // connected regions of one type
  uint32_t significant_regions = 0;          // with at least min_region points
  int regions_across_x = 0, regions_across_y = 0;  // most significant regions met along one line of x, of y
  // A cubic B-spline net that can follow them, at most one control point for each distinct x (y)
  // the points take, which is all a fit can determine; 0 where they take fewer than four (no cubic
  // net can be fitted), with the count in distinct_x (distinct_y).
  int suggested_control_x = 4, suggested_control_y = 4;
  size_t distinct_x = 0, distinct_y = 0;     // distinct sites along x and y, as the fit counts them (distinct_sites)
  std::vector<double> creases_x_mm, creases_y_mm;  // creases and steps across the scan (crease_detect)
};

// Throws FitError for fewer points than one neighbourhood or points all on a line in XY.
Characterization characterize(const PointCloud& cloud, const CharacterizeOptions& options = {});

}  // namespace dg::host
