// Reading STEP surfaces: our writer's files come back (clamped), units apply, damage is named.
#include "host/cad/step_reader.h"

#include <CppUTest/TestHarness.h>

#include <string>

#include "host/geometry/clamp.h"
#include "host/cad/step_writer.h"
#include "host/geometry/vec3.h"
#include "tests/support/sample_surfaces.h"

using namespace dg::host;

namespace {

std::string error_of(const std::string& text) {
  try {
    parse_step_surface(text, "in.stp");
  } catch (const StepError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_GROUP(StepReader){};

TEST(StepReader, ReadsBackWhatTheWriterWrote) {
  for (const BSplineSurface& s : {dg::test::clamped_sample(), dg::test::unclamped_sample()}) {
    const BSplineSurface back = parse_step_surface(step_text(s, StepOptions{}), "ours.stp");
    const BSplineSurface clamped = clamp_ends(s);  // the writer clamps
    LONGS_EQUAL(clamped.count_u, back.count_u);
    LONGS_EQUAL(clamped.count_v, back.count_v);
    CHECK(clamped.knots_u == back.knots_u);
    for (int a = 0; a <= 10; ++a)
      for (int b = 0; b <= 10; ++b) DOUBLES_EQUAL(0.0, norm(s.evaluate(a / 10.0, b / 10.0) - back.evaluate(a / 10.0, b / 10.0)), 1e-9);
  }
}

TEST(StepReader, AppliesTheLengthUnit) {
  std::string text = step_text(dg::test::clamped_sample(), StepOptions{});
  text.replace(text.find("SI_UNIT(.MILLI.,.METRE.)"), 24, "SI_UNIT($,.METRE.)");
  const BSplineSurface metres = parse_step_surface(text, "m.stp");
  DOUBLES_EQUAL(dg::test::clamped_sample().control[7].x * 1000, metres.control[7].x, 1e-9);
}

TEST(StepReader, NamesWhatIsWrong) {
  const std::string good = step_text(dg::test::clamped_sample(), StepOptions{});
  STRCMP_CONTAINS("not a STEP file", error_of("solid\n").c_str());
  STRCMP_CONTAINS("no DATA section", error_of("ISO-10303-21;\nHEADER;\nENDSEC;\n").c_str());
  std::string missing = good;
  const size_t point = missing.find("=CARTESIAN_POINT");
  missing.replace(point, 16, "=DIRECTION");  // a control point that is no point
  STRCMP_CONTAINS("is not a CARTESIAN_POINT", error_of(missing).c_str());
  std::string cut = good.substr(0, good.size() / 2);
  STRCMP_CONTAINS("in.stp", error_of(cut).c_str());
  std::string bad_knot = good;
  const size_t knot = bad_knot.find("(0.,0.3,");
  CHECK(knot != std::string::npos);
  bad_knot.replace(knot, 8, "(0.,x.3,");
  STRCMP_CONTAINS("in.stp #", error_of(bad_knot).c_str());
}

TEST(StepReader, RefusesSeveralFacesRatherThanReadOneUntrimmed) {
  const TrimmedFace face = dg::test::trimmed_sample();
  STRCMP_CONTAINS("holds 2 B-spline surfaces", error_of(step_faces_text({face, face}, StepOptions{})).c_str());
}
