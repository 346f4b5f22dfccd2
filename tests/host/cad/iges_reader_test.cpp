// Reading IGES entity 128: our writer's files come back exactly; units are applied; damaged files
// give errors that name the place.
#include "host/cad/iges_reader.h"

#include <CppUTest/TestHarness.h>

#include <string>

#include "host/cad/iges_writer.h"
#include "tests/support/sample_surfaces.h"

using namespace dg::host;

namespace {

std::string error_of(const std::string& text) {
  try {
    parse_iges_surface(text, "in.igs");
  } catch (const IgesError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_GROUP(IgesReader){};

TEST(IgesReader, ReadsBackWhatTheWriterWrote) {
  for (const BSplineSurface& s : {dg::test::clamped_sample(), dg::test::unclamped_sample()}) {
    const BSplineSurface back = parse_iges_surface(iges_text(s, IgesOptions{}), "ours.igs");
    LONGS_EQUAL(s.count_u, back.count_u);
    LONGS_EQUAL(s.degree_v, back.degree_v);
    CHECK(s.knots_u == back.knots_u);
    CHECK(s.knots_v == back.knots_v);
    for (size_t k = 0; k < s.control.size(); ++k) {
      DOUBLES_EQUAL(s.control[k].x, back.control[k].x, 0);
      DOUBLES_EQUAL(s.control[k].z, back.control[k].z, 0);
    }
  }
}

TEST(IgesReader, AppliesTheUnitsOfTheGlobalSection) {
  std::string text = iges_text(dg::test::clamped_sample(), IgesOptions{});
  // Our writer says scale 1.0, units 2 (mm), 2HMM; make it 1 (inches) and 2HIN.
  const size_t at = text.find("1.0,2,");
  CHECK(at != std::string::npos);
  text.replace(at, 6, "1.0,1,");
  text.replace(text.find("2HMM"), 4, "2HIN");
  const BSplineSurface inches = parse_iges_surface(text, "in.igs");
  DOUBLES_EQUAL(dg::test::clamped_sample().control[7].x * 25.4, inches.control[7].x, 1e-9);
}

TEST(IgesReader, NamesWhatIsWrongAndWhere) {
  const std::string good = iges_text(dg::test::clamped_sample(), IgesOptions{});
  STRCMP_CONTAINS("not an IGES line", error_of("hello\n").c_str());
  STRCMP_CONTAINS("not an IGES file", error_of(good.substr(0, 81)).c_str());
  std::string cut = good;
  cut.erase(cut.find("P      2\n") - 72, 81);  // one parameter line gone
  STRCMP_CONTAINS("lie outside the parameter section", error_of(cut).c_str());
  std::string nan = good;
  nan.replace(nan.find("0.3,"), 4, "NaN,");
  STRCMP_CONTAINS("a knot is not a finite number: 'NaN'", error_of(nan).c_str());
  std::string rational = good;
  // The third parameter line starts with weights (after the knots); make the first one 2.
  rational.replace(rational.find("P      2\n") + 9, 2, "2.");
  STRCMP_CONTAINS("rational surface", error_of(rational).c_str());
}

TEST(IgesReader, RefusesTrimmedFacesRatherThanReadOneUntrimmed) {
  STRCMP_CONTAINS("trimmed surface (entity 144)",
                  error_of(iges_faces_text({dg::test::trimmed_sample()}, IgesOptions{})).c_str());
}
