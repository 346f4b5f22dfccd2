// Our side of the anchors (scripts/anchors.py): a 32 x 32 bicubic least-squares fit of points the
// script wrote, and OpenCASCADE's GeomAPI_PointsToBSplineSurface on a grid of them, each timed
// and its RMS residual printed as "name seconds rms_mm" lines for the script to set beside SciPy's.
#include <GeomAPI_PointsToBSplineSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array2OfReal.hxx>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "host/fit/bspline_fit.h"
#include "host/parallel/memory_reuse.h"

using namespace dg::host;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// x, y, z as little-endian doubles, one point after another.
bool read_points(const char* path, std::vector<Point3>& points) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  double xyz[3];
  while (in.read(reinterpret_cast<char*>(xyz), sizeof xyz)) points.push_back({xyz[0], xyz[1], xyz[2]});
  return !points.empty();
}

double ours(const std::vector<Point3>& points, int count, double& rms) {
  PointCloud cloud;
  cloud.points = points;
  const Parameters p = parameterize(cloud, Parameterization::kTableXy);
  LsqSpec spec;
  spec.knots_u = spec.knots_v = clamped_uniform_knots(count, 3);
  const auto t0 = std::chrono::steady_clock::now();
  const BSplineSurface s = fit_least_squares(cloud.points, p, nullptr, spec);
  const double seconds = seconds_since(t0);
  double sum_sq = 0;
  for (size_t k = 0; k < points.size(); ++k) {
    const double d = points[k].z - s.evaluate(p.uv[k].u, p.uv[k].v).z;
    sum_sq += d * d;
  }
  rms = std::sqrt(sum_sq / static_cast<double>(points.size()));
  return seconds;
}

// A rows x columns grid (x fastest) as heights over equally spaced x and y.
double occ_approximation(const std::vector<Point3>& points, int columns, int rows, double tolerance_mm, double& rms,
                   int& poles_u, int& poles_v) {
  TColStd_Array2OfReal z(1, columns, 1, rows);
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < columns; ++i) z(i + 1, j + 1) = points[static_cast<size_t>(j) * columns + i].z;
  }
  const double x0 = points.front().x, y0 = points.front().y;
  const double dx = (points.back().x - x0) / (columns - 1), dy = (points.back().y - y0) / (rows - 1);
  const auto t0 = std::chrono::steady_clock::now();
  GeomAPI_PointsToBSplineSurface approx;
  approx.Init(z, x0, dx, y0, dy, 3, 3, GeomAbs_C2, tolerance_mm);
  const double seconds = seconds_since(t0);
  if (!approx.IsDone()) return -1;
  const Handle(Geom_BSplineSurface) s = approx.Surface();
  poles_u = s->NbUPoles();
  poles_v = s->NbVPoles();
  double sum_sq = 0;
  for (const Point3& q : points) {
    const gp_Pnt at = s->Value(q.x, q.y);  // the height-field form is parameterized by x and y
    sum_sq += (q.z - at.Z()) * (q.z - at.Z());
  }
  rms = std::sqrt(sum_sq / static_cast<double>(points.size()));
  return seconds;
}

}  // namespace

int main(int argc, char** argv) {
  tune_memory(argv, Restart::kAlways);  // huge pages, freed blocks kept (memory_reuse.h)
  if (argc < 3) {
    std::fprintf(stderr, "usage: anchor_fit lsq POINTS.f64 | occ POINTS.f64 COLUMNS ROWS TOLERANCE_MM\n");
    return 2;
  }
  std::vector<Point3> points;
  if (!read_points(argv[2], points)) {
    std::fprintf(stderr, "anchor_fit: cannot read %s\n", argv[2]);
    return 1;
  }
  const std::string mode = argv[1];
  if (mode == "lsq") {
    double rms = 0;
    const double seconds = ours(points, 32, rms);
    std::printf("ours %.4f %.6f\n", seconds, rms);
    return 0;
  }
  if (mode == "occ" && argc >= 6) {
    double rms = 0;
    int pu = 0, pv = 0;
    const double seconds = occ_approximation(points, std::atoi(argv[3]), std::atoi(argv[4]), std::atof(argv[5]), rms, pu, pv);
    if (seconds < 0) {
      std::printf("occ failed\n");
      return 1;
    }
    std::printf("occ %.4f %.6f %dx%d\n", seconds, rms, pu, pv);
    return 0;
  }
  std::fprintf(stderr, "anchor_fit: unknown mode %s\n", argv[1]);
  return 2;
}
