// Uniform subdivision of each knot span, doubled until the chord tolerance holds.
#include "host/geometry/tessellate.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <stdexcept>

#include "host/geometry/face_mesh.h"
#include "host/geometry/triangle_mesh.h"
#include "host/geometry/vec3.h"

namespace dg::host {
namespace {

// Parameters: every distinct knot in the domain, each span cut into `per_span` equal parts.
std::vector<double> grid_parameters(const std::vector<double>& knots, double lo, double hi, int per_span) {
  const std::vector<double> distinct = distinct_knots(knots, lo, hi);
  std::vector<double> t;
  for (size_t s = 0; s + 1 < distinct.size(); ++s) {
    for (int k = 0; k < per_span; ++k) t.push_back(distinct[s] + (distinct[s + 1] - distinct[s]) * k / per_span);
  }
  t.push_back(distinct.back());
  return t;
}

// Distance from p to the segment a-b.
double to_segment(const Point3& p, const Point3& a, const Point3& b) {
  const Point3 d = b - a;
  const double len2 = dot(d, d);
  const double t = len2 > 0 ? std::clamp(dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
  return norm(p - (a + t * d));
}

}  // namespace

double distance_to_triangle(const Point3& p, const Point3& a, const Point3& b, const Point3& c) {
  int feature = 0;
  return norm(p - closest_on_triangle(p, a, b, c, &feature));
}

Mesh tessellate(const BSplineSurface& s, double chord_mm, size_t max_triangles) {
  if (!(chord_mm > 0)) throw std::invalid_argument("the chord tolerance must be a positive number of mm");
  int per_u = 1, per_v = 1;
  for (;;) {
    const std::vector<double> us = grid_parameters(s.knots_u, s.u_min(), s.u_max(), per_u);
    const std::vector<double> vs = grid_parameters(s.knots_v, s.v_min(), s.v_max(), per_v);
    const size_t nu = us.size(), nv = vs.size();
    if (2 * (nu - 1) * (nv - 1) > max_triangles) {
      throw std::invalid_argument("a chord tolerance of " + std::to_string(chord_mm) + " mm needs more than " +
                                  std::to_string(max_triangles) + " triangles");
    }
    Mesh mesh;
    mesh.vertices.resize(nu * nv);
    for (size_t i = 0; i < nu; ++i)
      for (size_t j = 0; j < nv; ++j) mesh.vertices[i * nv + j] = s.evaluate(us[i], vs[j]);
    // Check each cell's centre and its edge midpoints along u and v against its two triangles.
    double worst_u = 0, worst_v = 0;
    for (size_t i = 0; i + 1 < nu; ++i) {
      for (size_t j = 0; j + 1 < nv; ++j) {
        const uint32_t a = static_cast<uint32_t>(i * nv + j), b = static_cast<uint32_t>((i + 1) * nv + j),
                       c = static_cast<uint32_t>((i + 1) * nv + j + 1), d = static_cast<uint32_t>(i * nv + j + 1);
        const Point3 &pa = mesh.vertices[a], &pb = mesh.vertices[b], &pc = mesh.vertices[c], &pd = mesh.vertices[d];
        const double um = 0.5 * (us[i] + us[i + 1]), vm = 0.5 * (vs[j] + vs[j + 1]);
        const Point3 centre = s.evaluate(um, vm);
        const double e_centre = std::min(distance_to_triangle(centre, pa, pb, pc), distance_to_triangle(centre, pa, pc, pd));
        const double e_u = to_segment(s.evaluate(um, vs[j]), pa, pb);  // an edge along u
        const double e_v = to_segment(s.evaluate(us[i], vm), pa, pd);  // an edge along v
        worst_u = std::max({worst_u, e_u, 0.5 * e_centre});
        worst_v = std::max({worst_v, e_v, 0.5 * e_centre});
        mesh.chord_error_mm = std::max({mesh.chord_error_mm, e_centre, e_u, e_v});
        mesh.triangles.push_back({a, b, c});
        mesh.triangles.push_back({a, c, d});
      }
    }
    if (mesh.chord_error_mm <= chord_mm) return mesh;
    if (worst_u >= worst_v) per_u *= 2;
    else per_v *= 2;
  }
}

namespace {

// A uniform grid of n_u x n_v points over a face's surface, and the largest deviation of the
// surface from its triangles at the cells' centres.
Mesh uniform_grid(const BSplineSurface& s, int nu, int nv) {
  Mesh mesh;
  mesh.vertices.resize(static_cast<size_t>(nu) * nv);
  auto u_at = [&](int i) { return s.u_min() + (s.u_max() - s.u_min()) * i / (nu - 1); };
  auto v_at = [&](int j) { return s.v_min() + (s.v_max() - s.v_min()) * j / (nv - 1); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) mesh.vertices[static_cast<size_t>(i) * nv + j] = s.evaluate(u_at(i), v_at(j));
  for (int i = 0; i + 1 < nu; ++i) {
    for (int j = 0; j + 1 < nv; ++j) {
      const uint32_t a = static_cast<uint32_t>(i * nv + j), b = static_cast<uint32_t>((i + 1) * nv + j),
                     c = static_cast<uint32_t>((i + 1) * nv + j + 1), d = static_cast<uint32_t>(i * nv + j + 1);
      const Point3 centre = s.evaluate(0.5 * (u_at(i) + u_at(i + 1)), 0.5 * (v_at(j) + v_at(j + 1)));
      const Point3 &pa = mesh.vertices[a], &pb = mesh.vertices[b], &pc = mesh.vertices[c], &pd = mesh.vertices[d];
      mesh.chord_error_mm = std::max(mesh.chord_error_mm, std::min(distance_to_triangle(centre, pa, pb, pc),
                                                                   distance_to_triangle(centre, pa, pc, pd)));
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
    }
  }
  return mesh;
}

}  // namespace

Mesh tessellate_faces(const std::vector<TrimmedFace>& faces, double chord_mm, double cell_mm, size_t max_triangles) {
  if (!(chord_mm > 0)) throw std::invalid_argument("the chord tolerance must be a positive number of mm");
  Mesh out;
  for (const TrimmedFace& face : faces) {
    // A uniform grid no coarser than cell_mm in XY, halved until within the chord tolerance.
    const BSplineSurface& s = face.surface;
    const double width = std::fabs(s.at(s.count_u - 1, 0).x - s.at(0, 0).x);
    const double depth = std::fabs(s.at(0, s.count_v - 1).y - s.at(0, 0).y);
    int nu = std::max(2, static_cast<int>(std::ceil(width / cell_mm)) + 1);
    int nv = std::max(2, static_cast<int>(std::ceil(depth / cell_mm)) + 1);
    Mesh mesh;
    for (;;) {
      if (2.0 * (nu - 1) * (nv - 1) > static_cast<double>(max_triangles)) {
        throw std::invalid_argument("the faces need more than " + std::to_string(max_triangles) + " triangles");
      }
      mesh = uniform_grid(s, nu, nv);
      if (mesh.chord_error_mm <= chord_mm) break;
      nu = 2 * nu - 1;
      nv = 2 * nv - 1;
    }
    append_face_mesh(face, mesh, nu, nv, out);
    if (out.triangles.size() > max_triangles) {
      throw std::invalid_argument("the faces need more than " + std::to_string(max_triangles) + " triangles");
    }
    out.chord_error_mm = std::max(out.chord_error_mm, mesh.chord_error_mm);
  }
  return out;
}

}  // namespace dg::host
