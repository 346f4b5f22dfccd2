// Subdivision of the knot spans, halved where the surface errs until the chord tolerance holds.
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

Mesh tessellate(const BSplineSurface& s, double chord_mm, size_t max_triangles, double angle_deg) {
  if (!(chord_mm > 0)) throw std::invalid_argument("the chord tolerance must be a positive number of mm");
  if (!(angle_deg >= 0 && angle_deg < 90)) throw std::invalid_argument("the angle tolerance must be 0 (none) to under 90 degrees");
  const double cos_angle = std::cos(angle_deg * M_PI / 180);
  // A tensor grid whose u and v lines start at the knots; each pass halves only the u strips and
  // v strips where a cell errs, so lines gather where the surface bends and the mesh stays
  // conforming (every cell a quad of four grid points, no T-junctions).
  std::vector<double> us = grid_parameters(s.knots_u, s.u_min(), s.u_max(), 1);
  std::vector<double> vs = grid_parameters(s.knots_v, s.v_min(), s.v_max(), 1);
  for (;;) {
    const size_t nu = us.size(), nv = vs.size();
    if (2 * (nu - 1) * (nv - 1) > max_triangles) {
      throw std::invalid_argument("a chord tolerance of " + std::to_string(chord_mm) + " mm needs more than " +
                                  std::to_string(max_triangles) + " triangles");
    }
    Mesh mesh;
    mesh.vertices.resize(nu * nv);
    for (size_t i = 0; i < nu; ++i)
      for (size_t j = 0; j < nv; ++j) mesh.vertices[i * nv + j] = s.evaluate(us[i], vs[j]);
    // Each cell's centre and its edge midpoints along u and v against its two triangles; an edge
    // that errs marks its strip, a centre that errs with both edges inside marks both strips.
    std::vector<char> split_u(nu - 1, 0), split_v(nv - 1, 0);
    // Each edge's midpoint error once: neighbouring cells share their edges.
    std::vector<double> edge_u((nu - 1) * nv), edge_v(nu * (nv - 1));
    for (size_t i = 0; i + 1 < nu; ++i)
      for (size_t j = 0; j < nv; ++j)
        edge_u[i * nv + j] = to_segment(s.evaluate(0.5 * (us[i] + us[i + 1]), vs[j]), mesh.vertices[i * nv + j],
                                        mesh.vertices[(i + 1) * nv + j]);
    for (size_t i = 0; i < nu; ++i)
      for (size_t j = 0; j + 1 < nv; ++j)
        edge_v[i * (nv - 1) + j] = to_segment(s.evaluate(us[i], 0.5 * (vs[j] + vs[j + 1])), mesh.vertices[i * nv + j],
                                              mesh.vertices[i * nv + j + 1]);
    for (size_t i = 0; i + 1 < nu; ++i) {
      for (size_t j = 0; j + 1 < nv; ++j) {
        const uint32_t a = static_cast<uint32_t>(i * nv + j), b = static_cast<uint32_t>((i + 1) * nv + j),
                       c = static_cast<uint32_t>((i + 1) * nv + j + 1), d = static_cast<uint32_t>(i * nv + j + 1);
        const Point3 &pa = mesh.vertices[a], &pb = mesh.vertices[b], &pc = mesh.vertices[c], &pd = mesh.vertices[d];
        const double um = 0.5 * (us[i] + us[i + 1]), vm = 0.5 * (vs[j] + vs[j + 1]);
        Point3 centre, su, sv;
        if (angle_deg > 0) s.evaluate(um, vm, centre, su, sv);
        else centre = s.evaluate(um, vm);
        const double e_centre = std::min(distance_to_triangle(centre, pa, pb, pc), distance_to_triangle(centre, pa, pc, pd));
        // The angle tolerance: both triangles' normals within it of the surface's at the centre.
        if (angle_deg > 0) {
          const Point3 n = cross(su, sv), n1 = cross(pb - pa, pc - pa), n2 = cross(pc - pa, pd - pa);
          const double len = norm(n);
          for (const Point3& t : {n1, n2}) {
            if (len > 0 && norm(t) > 0 && dot(n, t) < cos_angle * len * norm(t)) split_u[i] = split_v[j] = 1;
          }
        }
        // Both edges of the cell along u (and along v): a strip's two sides can bend differently.
        const double e_u = std::max(edge_u[i * nv + j], edge_u[i * nv + j + 1]);
        const double e_v = std::max(edge_v[i * (nv - 1) + j], edge_v[(i + 1) * (nv - 1) + j]);
        mesh.chord_error_mm = std::max({mesh.chord_error_mm, e_centre, e_u, e_v});
        if (e_u > chord_mm) split_u[i] = 1;
        if (e_v > chord_mm) split_v[j] = 1;
        if (e_centre > chord_mm && e_u <= chord_mm && e_v <= chord_mm) split_u[i] = split_v[j] = 1;
        mesh.triangles.push_back({a, b, c});
        mesh.triangles.push_back({a, c, d});
      }
    }
    // Every cell beyond the chord or the angle marked a strip: none marked means both hold.
    const auto marked = [](char c) { return c != 0; };
    if (std::none_of(split_u.begin(), split_u.end(), marked) && std::none_of(split_v.begin(), split_v.end(), marked)) return mesh;
    // A strip still erring at a millionth of its domain will not stop erring: rounding or a cusp,
    // not curvature. Uniform halving ran into max_triangles within a few passes; strips halved one
    // at a time would instead go on for ever, so this is where refinement gives up.
    auto refined = [&](const std::vector<double>& t, const std::vector<char>& split) {
      const double smallest = 1e-6 * (t.back() - t.front());
      std::vector<double> out{t.front()};
      for (size_t k = 0; k + 1 < t.size(); ++k) {
        if (split[k]) {
          if (!(t[k + 1] - t[k] > smallest)) {
            throw std::invalid_argument("a chord tolerance of " + std::to_string(chord_mm) +
                                        " mm cannot be reached: the surface still errs on a millionth of its domain");
          }
          out.push_back(0.5 * (t[k] + t[k + 1]));
        }
        out.push_back(t[k + 1]);
      }
      return out;
    };
    us = refined(us, split_u);
    vs = refined(vs, split_v);
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
