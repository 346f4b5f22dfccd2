// SURF.json: what is written reads back the same (surface, validation, uncertainty), and what the
// format does not define is refused with the field named.
#include "host/cad/surface_json.h"

#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <unistd.h>

#include "tests/support/sample_surfaces.h"

using namespace dg::host;

namespace {

FittedSurface fitted() {
  FittedSurface f;
  f.surface = dg::test::clamped_sample();
  f.has_fit = true;
  f.source = "part.scan";
  f.tolerance_mm = 0.025;
  f.tolerance_kept = true;
  f.noise_sigma_mm = 0.005;
  f.validation.checked = true;
  f.validation.passed = true;
  f.validation.folds = 5;
  f.validation.held_out_points = 250;
  f.validation.held_out_rms_mm = 0.006;
  f.validation.held_out_max_mm = 0.02;
  f.uncertainty.computed = true;
  f.uncertainty.sigma_mm = 0.005;
  f.uncertainty.sigma_from = "noise estimate";
  f.uncertainty.rows = 2;
  f.uncertainty.cols = 3;
  f.uncertainty.u_mm = {0.001, 0.002, 0.003, 0.004, 0.005, 0.006};
  f.uncertainty.max_mm = 0.006;
  f.uncertainty.mean_mm = 0.0035;
  return f;
}

std::string error_of(const std::string& text) {
  try {
    parse_surface_json(text, "s.json");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_GROUP(SurfaceJson){};

TEST(SurfaceJson, ReadsBackTheSurfaceItsValidationAndItsUncertainty) {
  const FittedSurface f = fitted();
  const FittedSurface back = parse_surface_json(surface_json_text(f), "s.json");
  LONGS_EQUAL(f.surface.count_u, back.surface.count_u);
  LONGS_EQUAL(f.surface.control.size(), back.surface.control.size());
  for (size_t i = 0; i < f.surface.control.size(); ++i) DOUBLES_EQUAL(f.surface.control[i].z, back.surface.control[i].z, 0);
  CHECK(back.validation.checked && back.validation.passed);
  LONGS_EQUAL(250, back.validation.held_out_points);
  DOUBLES_EQUAL(0.02, back.validation.held_out_max_mm, 0);
  CHECK(back.uncertainty.computed);
  LONGS_EQUAL(2, back.uncertainty.rows);
  LONGS_EQUAL(3, back.uncertainty.cols);
  DOUBLES_EQUAL(0.006, back.uncertainty.u_mm[5], 0);
  STRCMP_EQUAL("noise estimate", back.uncertainty.sigma_from.c_str());
}

TEST(SurfaceJson, RefusesAModelTheFormatDoesNotDefine) {
  std::string text = surface_json_text(fitted());
  const size_t at = text.find("\"bspline\"");
  text.replace(at, 9, "\"nurbs\"");
  STRCMP_CONTAINS("\"model\" is 'nurbs'", error_of(text).c_str());
}

TEST(SurfaceJson, RefusesAKnotVectorOfTheWrongLength) {
  FittedSurface f = fitted();
  f.surface.knots_u.pop_back();
  CHECK(!error_of(surface_json_text(f)).empty());
}

// Found by fuzzing: a number beyond a double's range escaped the reader as a JSON library error.
TEST(SurfaceJson, ANumberBeyondADoublesRangeIsAClearError) {
  std::string text = surface_json_text(fitted());
  const size_t at = text.find("\"knots_u\": [") + 12;
  text.insert(at, "5.1e23089,");
  STRCMP_CONTAINS("beyond the range of a double", error_of(text).c_str());
}

// Found by fuzzing: a fit section without its noise field read past the end of a JSON object.
TEST(SurfaceJson, AFitSectionWithoutItsNoiseFieldReadsAsNoEstimate) {
  std::string text = surface_json_text(fitted());
  const size_t at = text.find("\"noise_sigma_mm\"");
  text.replace(at, 16, "\"noise_sigma_xx\"");
  DOUBLES_EQUAL(0.0, parse_surface_json(text, "s.json").noise_sigma_mm, 0);
}

// Found by fuzzing: a float where a whole number belongs (2e59 control points) was converted to an
// int, which is undefined.
TEST(SurfaceJson, AFloatWhereAWholeNumberBelongsIsRefused) {
  std::string text = surface_json_text(fitted());
  const size_t at = text.find("\"control_count\": [") + 18;
  const size_t end = text.find(']', at);
  text.replace(at, end - at, "2.2e59, 5");
  STRCMP_CONTAINS("\"control_count\" must be a whole number", error_of(text).c_str());
}

namespace {

// Two trimmed faces over the sample surface's box: a square with a square hole, and the hole.
FittedSurface with_faces() {
  FittedSurface f = fitted();
  const BSplineSurface s = dg::test::clamped_sample();
  const Point3& a = s.at(0, 0);
  const Point3& b = s.at(s.count_u - 1, s.count_v - 1);
  const double x0 = a.x, x1 = b.x, y0 = a.y, y1 = b.y, mx = 0.5 * (x0 + x1), my = 0.5 * (y0 + y1);
  const double hx = 0.25 * (x1 - x0), hy = 0.25 * (y1 - y0);
  TrimmedFace outer;
  outer.surface = s;
  outer.loops = {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, {{mx - hx, my - hy}, {mx - hx, my + hy}, {mx + hx, my + hy}, {mx + hx, my - hy}}};
  TrimmedFace inner;
  inner.surface = s;
  inner.loops = {{{mx - hx, my - hy}, {mx + hx, my - hy}, {mx + hx, my + hy}, {mx - hx, my + hy}}};
  f.faces = {outer, inner};
  f.surface = BSplineSurface{};
  return f;
}

}  // namespace

TEST(SurfaceJson, TrimmedFacesReadBackWithTheirLoops) {
  const FittedSurface f = with_faces();
  const FittedSurface back = parse_surface_json(surface_json_text(f), "SURF.json");
  LONGS_EQUAL(2, back.faces.size());
  for (size_t k = 0; k < 2; ++k) {
    LONGS_EQUAL(f.faces[k].loops.size(), back.faces[k].loops.size());
    for (size_t l = 0; l < f.faces[k].loops.size(); ++l) {
      for (size_t v = 0; v < f.faces[k].loops[l].size(); ++v) {
        DOUBLES_EQUAL(f.faces[k].loops[l][v].x, back.faces[k].loops[l][v].x, 0);
        DOUBLES_EQUAL(f.faces[k].loops[l][v].y, back.faces[k].loops[l][v].y, 0);
      }
    }
    LONGS_EQUAL(f.faces[k].surface.control.size(), back.faces[k].surface.control.size());
  }
  CHECK(inside_face(back.faces[0], f.faces[0].loops[0][0].x + 1e-3, f.faces[0].loops[0][0].y + 1e-3));
}

TEST(SurfaceJson, AFaceWhoseOuterLoopRunsClockwiseIsRefused) {
  FittedSurface f = with_faces();
  std::reverse(f.faces[1].loops[0].begin(), f.faces[1].loops[0].end());
  try {
    parse_surface_json(surface_json_text(f), "SURF.json");
    FAIL("a clockwise outer loop was accepted");
  } catch (const std::runtime_error& e) {
    STRCMP_CONTAINS("counter-clockwise", e.what());
  }
}

TEST(SurfaceJson, ALoopBeyondItsSurfaceIsRefused) {
  FittedSurface f = with_faces();
  f.faces[1].loops[0][1].x += 1000;
  try {
    parse_surface_json(surface_json_text(f), "SURF.json");
    FAIL("a loop outside its surface was accepted");
  } catch (const std::runtime_error& e) {
    STRCMP_CONTAINS("outside the face's surface", e.what());
  }
}

// A face's uncertainty grid reads back node by node, the nodes outside the face as such.
TEST(SurfaceJson, AFacesUncertaintyGridReadsBackWithItsNodesOffTheFace) {
  FittedSurface f = with_faces();
  SurfaceUncertainty& u = f.faces[0].uncertainty;
  u.computed = true;
  u.sigma_mm = 0.002;
  u.sigma_from = "noise estimate";
  u.max_mm = 0.0011;
  u.mean_mm = 0.0004;
  u.rows = 2;
  u.cols = 3;
  u.u_mm = {0.0002, kOffFace, 0.0011, kOffFace, 0.0003, 0.0004};
  const std::string text = surface_json_text(f);
  STRCMP_CONTAINS("null", text.c_str());
  const FittedSurface back = parse_surface_json(text, "SURF.json");
  CHECK(back.faces[0].uncertainty.computed);
  CHECK(!back.faces[1].uncertainty.computed);
  DOUBLES_EQUAL(0.002, back.faces[0].uncertainty.sigma_mm, 0);
  DOUBLES_EQUAL(0.0011, back.faces[0].uncertainty.max_mm, 0);
  DOUBLES_EQUAL(0.0004, back.faces[0].uncertainty.mean_mm, 0);
  STRCMP_EQUAL("noise estimate", back.faces[0].uncertainty.sigma_from.c_str());
  LONGS_EQUAL(2, back.faces[0].uncertainty.rows);
  LONGS_EQUAL(3, back.faces[0].uncertainty.cols);
  for (size_t k = 0; k < u.u_mm.size(); ++k) DOUBLES_EQUAL(u.u_mm[k], back.faces[0].uncertainty.u_mm[k], 0);
}

// The single surface's grid covers the whole domain: a null node there is an error.
TEST(SurfaceJson, ANullNodeInTheSurfacesOwnUncertaintyGridIsRefused) {
  FittedSurface f = fitted();
  f.uncertainty.computed = true;
  f.uncertainty.sigma_mm = 0.002;
  f.uncertainty.rows = f.uncertainty.cols = 2;
  f.uncertainty.u_mm = {0.001, kOffFace, 0.001, 0.001};
  try {
    parse_surface_json(surface_json_text(f), "SURF.json");
    FAIL("a null node in a whole surface's grid was accepted");
  } catch (const std::runtime_error& e) {
    STRCMP_CONTAINS("uncertainty", e.what());
  }
}

TEST(SurfaceJson, ANegativeFaceUncertaintyIsRefused) {
  FittedSurface f = with_faces();
  f.faces[1].uncertainty.computed = true;
  f.faces[1].uncertainty.sigma_mm = 0.002;
  f.faces[1].uncertainty.max_mm = -0.001;
  f.faces[1].uncertainty.mean_mm = 0.0004;
  try {
    parse_surface_json(surface_json_text(f), "SURF.json");
    FAIL("a negative uncertainty was accepted");
  } catch (const std::runtime_error& e) {
    STRCMP_CONTAINS("face 2", e.what());
    STRCMP_CONTAINS("not a finite, non-negative number", e.what());
  }
}

// A fit whose numbers overflowed is refused, not written with null in a result's place: every
// part of the report is checked, and the message names the first that is no finite number.
TEST(SurfaceJson, AFitHoldingANumberThatIsNotFiniteIsNotWritten) {
  const std::string path = std::string(P_tmpdir) + "/dg_surface_json_" + std::to_string(getpid()) + "_not_finite.json";
  std::remove(path.c_str());
  auto refusal = [&](const FittedSurface& f) -> std::string {
    try {
      write_surface_json(path, f);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  };
  FittedSurface f = fitted();
  f.distance.count = 100;
  f.distance.rms = HUGE_VAL;
  STRCMP_CONTAINS("not written: the points' orthogonal distances came out as no finite number", refusal(f).c_str());
  f = fitted();
  f.surface.control[5].z = std::nan("");
  STRCMP_CONTAINS("the surface's control point 6", refusal(f).c_str());
  f = fitted();
  f.validation.held_out_max_mm = std::nan("");
  STRCMP_CONTAINS("the held-out points' errors", refusal(f).c_str());
  f = fitted();
  f.uncertainty.u_mm[4] = HUGE_VAL;
  STRCMP_CONTAINS("the surface's uncertainty grid", refusal(f).c_str());
  FILE* written = std::fopen(path.c_str(), "r");
  CHECK(written == nullptr);
  if (written) std::fclose(written);
  // The same fit with finite numbers is written.
  write_surface_json(path, fitted());
  written = std::fopen(path.c_str(), "r");
  CHECK(written != nullptr);
  if (written) std::fclose(written);
  std::remove(path.c_str());
}
