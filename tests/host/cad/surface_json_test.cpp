// SURF.json: what is written reads back the same (surface, validation, uncertainty), and what the
// format does not define is refused with the field named.
#include "host/cad/surface_json.h"

#include <CppUTest/TestHarness.h>

#include <stdexcept>
#include <string>

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
