// The inspection summary as JSON: the statistics and bands as measured, and the alignment that
// moved the points first (its transform and residuals), or null when there was none.
#include "host/inspect/inspection_json.h"

#include <CppUTest/TestHarness.h>

#include <nlohmann/json.hpp>

#include "tests/support/sample_surfaces.h"

using namespace dg::host;

namespace {

Inspection plane_inspection() {
  const BSplineSurface plane = dg::test::tilted_plane();
  return inspect({{5, 5, 1.5}, {10, 8, 0.75}, {15, 12, 1.0}}, plane, {0.1, 1.0});
}

}  // namespace

TEST_GROUP(InspectionJson){};

TEST(InspectionJson, CarriesTheAlignmentsTransformAndResiduals) {
  AlignmentSummary a;
  a.rotation = {{{0, -1, 0}, {1, 0, 0}, {0, 0, 1}}};
  a.translation_mm = {1.5, -2.0, 0.25};
  a.rotation_deg = 90;
  a.rms_before_mm = 0.4;
  a.rms_after_mm = 0.003;
  a.iterations = 7;
  a.converged = true;
  a.beyond_edge = 12;
  a.held = 3;
  const nlohmann::json j = nlohmann::json::parse(inspection_json_text(plane_inspection(), "p.csv", "s.json", &a));
  LONGS_EQUAL(12, j["alignment"]["points_beyond_edge"].get<int>());
  LONGS_EQUAL(3, j["alignment"]["freedoms_held"].get<int>());
  DOUBLES_EQUAL(-1.0, j["alignment"]["rotation"][0][1].get<double>(), 0);
  DOUBLES_EQUAL(-2.0, j["alignment"]["translation_mm"][1].get<double>(), 0);
  DOUBLES_EQUAL(0.003, j["alignment"]["rms_after_mm"].get<double>(), 0);
  LONGS_EQUAL(7, j["alignment"]["iterations"].get<int>());
  CHECK(j["alignment"]["converged"].get<bool>());
  LONGS_EQUAL(3, j["deviation"]["count"].get<int>());
}

TEST(InspectionJson, SaysWhenThePointsWereNotAligned) {
  const nlohmann::json j = nlohmann::json::parse(inspection_json_text(plane_inspection(), "p.csv", "s.json"));
  CHECK(j.contains("alignment"));
  CHECK(j["alignment"].is_null());
}

TEST(InspectionJson, NamesThePartSerialOperatorAndCompanyGivenAndOnlyThose) {
  ReportFields fields;
  fields.part = "lid \"4711\"";
  fields.operator_name = "A. Fitter";
  const nlohmann::json j = nlohmann::json::parse(inspection_json_text(plane_inspection(), "p.csv", "s.json", nullptr, nullptr, fields));
  STRCMP_EQUAL("lid \"4711\"", j["part"].get<std::string>().c_str());
  STRCMP_EQUAL("A. Fitter", j["operator"].get<std::string>().c_str());
  CHECK(!j.contains("serial"));
  CHECK(!j.contains("company"));
}

// Against a nominal the JSON says what it was and how many points the exact search left to its
// mesh, so a script can refuse an inspection that leaned on the mesh; against a fit, null.
TEST(InspectionJson, NamesTheNominalAndThePointsMeasuredOnItsMesh) {
  NominalNote note;
  note.summary = "STEP, 54 faces";
  note.measured_on_mesh = 3;
  note.mesh_deflection_mm = 0.005;
  const nlohmann::json j =
      nlohmann::json::parse(inspection_json_text(plane_inspection(), "p.csv", "part.stp", nullptr, nullptr, ReportFields{}, &note));
  STRCMP_EQUAL("STEP, 54 faces", j["nominal"]["summary"].get<std::string>().c_str());
  LONGS_EQUAL(3, j["nominal"]["points_measured_on_mesh"].get<int>());
  DOUBLES_EQUAL(0.005, j["nominal"]["mesh_deflection_mm"].get<double>(), 0);
  CHECK(nlohmann::json::parse(inspection_json_text(plane_inspection(), "p.csv", "s.json"))["nominal"].is_null());
}

// A datum alignment says so, with each datum's region, what it fixed and its RMS.
TEST(InspectionJson, ADatumAlignmentListsItsDatums) {
  AlignmentSummary a;
  a.datums.push_back({"A", 0, 40, 0, 4, 205, "tilt about x and y, height", 0.0021});
  a.datums.push_back({"B", 10, 30, 5, 25, 441, "rotation about z, x and y", 0.0018});
  const nlohmann::json j = nlohmann::json::parse(inspection_json_text(plane_inspection(), "p.csv", "s.json", &a));
  STRCMP_EQUAL("datums", j["alignment"]["method"].get<std::string>().c_str());
  LONGS_EQUAL(2, j["alignment"]["datums"].size());
  STRCMP_EQUAL("B", j["alignment"]["datums"][1]["name"].get<std::string>().c_str());
  DOUBLES_EQUAL(25, j["alignment"]["datums"][1]["box_mm"][1][1].get<double>(), 0);
  LONGS_EQUAL(441, j["alignment"]["datums"][1]["points"].get<int>());
  STRCMP_EQUAL("tilt about x and y, height", j["alignment"]["datums"][0]["fixes"].get<std::string>().c_str());
  AlignmentSummary best;
  STRCMP_EQUAL("best fit",
               nlohmann::json::parse(inspection_json_text(plane_inspection(), "p.csv", "s.json", &best))["alignment"]["method"]
                   .get<std::string>()
                   .c_str());
}

TEST(InspectionJson, CountsThePointsBeyondTheSurfacesEdge) {
  const BSplineSurface plane = dg::test::tilted_plane();  // over 0..40 x 0..30 mm
  const Inspection beyond = inspect({{5, 5, 1.5}, {60, 8, 0.75}, {-5, 12, 1.0}}, plane, {0.1});
  const nlohmann::json j = nlohmann::json::parse(inspection_json_text(beyond, "p.csv", "s.json"));
  LONGS_EQUAL(2, j["beyond_edge"].get<int>());
  LONGS_EQUAL(3, j["points"].get<int>());
  LONGS_EQUAL(1, j["deviation"]["count"].get<int>());  // of the points over the surface
  LONGS_EQUAL(0, nlohmann::json::parse(inspection_json_text(plane_inspection(), "p.csv", "s.json"))["beyond_edge"].get<int>());
}
