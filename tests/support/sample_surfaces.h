// Surfaces for tests: a plane, a clamped fit-like net and an unclamped uniform net like the device's.
#pragma once
#include <cmath>

#include "host/geometry/bspline_surface.h"
#include "host/geometry/trimmed_face.h"

namespace dg::test {

// A bilinear patch that is exactly a plane: z = 1 + 0.1 x over 0..40 x 0..30 mm.
inline host::BSplineSurface tilted_plane() {
  host::BSplineSurface s;
  s.degree_u = s.degree_v = 1;
  s.count_u = s.count_v = 2;
  s.knots_u = s.knots_v = {0, 0, 1, 1};
  s.control = {{0, 0, 1}, {0, 30, 1}, {40, 0, 5}, {40, 30, 5}};
  return s;
}

// A 6 x 5 bicubic-by-quadratic net with an interior double knot in v.
inline host::BSplineSurface clamped_sample() {
  host::BSplineSurface s;
  s.degree_u = 3;
  s.degree_v = 2;
  s.count_u = 6;
  s.count_v = 5;
  s.knots_u = {0, 0, 0, 0, 0.3, 0.6, 1, 1, 1, 1};
  s.knots_v = {0, 0, 0, 0.25, 0.25, 1, 1, 1};
  for (int i = 0; i < s.count_u; ++i) {
    for (int j = 0; j < s.count_v; ++j) {
      s.control.push_back({8.0 * i + 0.3 * j, 7.5 * j, 2.0 + std::sin(i * 0.9) * std::cos(j * 0.7) + 0.01 * i * j});
    }
  }
  return s;
}

// A 5 x 5 uniform cubic net on knots (i - 3) / 2, as `digitizer pull` writes the device's net.
inline host::BSplineSurface unclamped_sample() {
  host::BSplineSurface s;
  s.count_u = s.count_v = 5;
  for (int i = 0; i <= 8; ++i) s.knots_u.push_back((i - 3) / 2.0);
  s.knots_v = s.knots_u;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) {
      s.control.push_back({20.0 * (i - 1) / 2.0, 15.0 * (j - 1) / 2.0, 3.0 + 0.4 * std::cos(i + 0.5 * j)});
    }
  }
  return s;
}

// One bicubic Bezier patch (knots 0,0,0,0,1,1,1,1), as `fit --model bezier` writes it.
inline host::BSplineSurface bezier_sample() {
  host::BSplineSurface s;
  s.count_u = s.count_v = 4;
  s.knots_u = s.knots_v = {0, 0, 0, 0, 1, 1, 1, 1};
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) s.control.push_back({12.0 * i, 10.0 * j, 4.0 + ((i == 1 || i == 2) && (j == 1 || j == 2) ? 3.0 : 0.5 * i)});
  }
  return s;
}

// The clamped sample as a face trimmed to the triangle below its diagonal.
inline host::TrimmedFace trimmed_sample() {
  host::TrimmedFace face;
  face.surface = clamped_sample();
  const host::Point3& a = face.surface.at(0, 0);
  const host::Point3& b = face.surface.at(face.surface.count_u - 1, face.surface.count_v - 1);
  face.loops = {{{a.x, a.y}, {b.x, a.y}, {b.x, b.y}}};
  return face;
}

}  // namespace dg::test
