// Parameterization of measured points (Koivunen and Bajcsy 1992, eq. 6-7) and the table-XY height-field map.
#include "host/fit/parameterize.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "host/fit/fit_error.h"
#include "host/geometry/vec3.h"

namespace dg::host {

Parameterization parse_parameterization(const std::string& name) {
  if (name == "xy") return Parameterization::kTableXy;
  if (name == "uniform") return Parameterization::kUniform;
  if (name == "chord") return Parameterization::kChordLength;
  if (name == "centripetal") return Parameterization::kCentripetal;
  throw FitError("unknown parameterization '" + name + "' (xy, uniform, chord, centripetal)");
}

const char* parameterization_name(Parameterization p) {
  switch (p) {
    case Parameterization::kTableXy: return "xy";
    case Parameterization::kUniform: return "uniform";
    case Parameterization::kChordLength: return "chord";
    case Parameterization::kCentripetal: return "centripetal";
  }
  return "?";
}

namespace {

// The step weight of eq. 6 (chord), eq. 7 (centripetal) or 1 (uniform).
double step_weight(Parameterization kind, double distance) {
  switch (kind) {
    case Parameterization::kChordLength: return distance;
    case Parameterization::kCentripetal: return std::sqrt(distance);
    default: return 1.0;
  }
}

// Cumulative normalised parameters from step weights: t_0 = 0, t_n = 1.
std::vector<double> cumulate(const std::vector<double>& steps) {
  std::vector<double> t(steps.size() + 1, 0.0);
  for (size_t i = 0; i < steps.size(); ++i) t[i + 1] = t[i] + steps[i];
  const double total = t.back();
  for (double& value : t) value = total > 0 ? value / total : 0.0;
  if (!t.empty()) t.back() = 1.0;
  return t;
}

Parameters table_xy(const PointCloud& cloud) {
  Parameters p;
  p.kind = Parameterization::kTableXy;
  double sx = 0, sy = 0;
  p.x_min = p.y_min = HUGE_VAL;
  p.x_max = p.y_max = -HUGE_VAL;
  for (const auto& q : cloud.points) {
    p.x_min = std::min(p.x_min, q.x);
    p.x_max = std::max(p.x_max, q.x);
    p.y_min = std::min(p.y_min, q.y);
    p.y_max = std::max(p.y_max, q.y);
    sx += q.x;
    sy += q.y;
  }
  // Collinear in XY (a single scan line, or points along any one line): the smaller principal
  // spread of the XY positions vanishes.
  const double n = static_cast<double>(cloud.points.size());
  const double mx = sx / n, my = sy / n;
  double cxx = 0, cyy = 0, cxy = 0;
  for (const auto& q : cloud.points) {
    cxx += (q.x - mx) * (q.x - mx);
    cyy += (q.y - my) * (q.y - my);
    cxy += (q.x - mx) * (q.y - my);
  }
  const double trace = cxx + cyy, det = cxx * cyy - cxy * cxy;
  const double smaller = 0.5 * (trace - std::sqrt(std::max(0.0, trace * trace - 4 * det)));
  if (!(trace > 0) || smaller <= 1e-12 * trace) {
    throw FitError("the points are collinear in XY (a single scan line?): a surface needs an area");
  }
  p.uv.resize(cloud.points.size());
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    p.uv[i].u = (cloud.points[i].x - p.x_min) / (p.x_max - p.x_min);
    p.uv[i].v = (cloud.points[i].y - p.y_min) / (p.y_max - p.y_min);
  }
  return p;
}

}  // namespace

Parameters parameterize(const PointCloud& cloud, Parameterization kind) {
  if (cloud.points.size() < 4) throw FitError("too few points for a surface: " + std::to_string(cloud.points.size()));
  if (kind == Parameterization::kTableXy) return table_xy(cloud);
  if (!cloud.line) {
    throw FitError(std::string("the ") + parameterization_name(kind) +
                   " parameterization needs scan lines: give a 'line' column or run 'digitizer segment' first");
  }
  // Points of each line, in stream order.
  std::map<uint32_t, std::vector<size_t>> lines;
  for (size_t i = 0; i < cloud.points.size(); ++i) lines[(*cloud.line)[i]].push_back(i);
  if (lines.size() < 2) throw FitError("a single scan line cannot determine a surface");
  Parameters p;
  p.kind = kind;
  p.uv.resize(cloud.points.size());
  std::vector<Point3> centroids;
  Point3 first_direction{};
  for (auto& [id, members] : lines) {
    if (members.size() < 2) throw FitError("scan line " + std::to_string(id) + " has a single point");
    const Point3 direction = cloud.points[members.back()] - cloud.points[members.front()];
    if (centroids.empty()) first_direction = direction;
    if (dot(direction, first_direction) < 0) std::reverse(members.begin(), members.end());
    std::vector<double> steps;
    Point3 centroid;
    for (size_t k = 0; k < members.size(); ++k) {
      centroid += cloud.points[members[k]];
      if (k > 0) steps.push_back(step_weight(kind, norm(cloud.points[members[k]] - cloud.points[members[k - 1]])));
    }
    const std::vector<double> t = cumulate(steps);
    for (size_t k = 0; k < members.size(); ++k) p.uv[members[k]].u = t[k];
    centroids.push_back((1.0 / static_cast<double>(members.size())) * centroid);
  }
  std::vector<double> across;
  for (size_t l = 1; l < centroids.size(); ++l) across.push_back(step_weight(kind, norm(centroids[l] - centroids[l - 1])));
  const std::vector<double> v = cumulate(across);
  if (!(v.back() > 0) || v[v.size() - 2] >= 1.0) throw FitError("the scan lines lie on top of each other");
  size_t l = 0;
  for (const auto& [id, members] : lines) {
    for (size_t m : members) p.uv[m].v = v[l];
    ++l;
  }
  return p;
}

}  // namespace dg::host
