// The calibration file: written and read back, refused whole when any part is wrong, and the
// correction it makes, including to a scan file's own points.
#include <CppUTest/TestHarness.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "host/scan/scan_file.h"
#include "host/scan/table_calibration.h"

using namespace dg::host;

namespace {

TableCalibration three_by_two() {
  TableCalibration c;
  c.created_utc = "2026-11-26T05:00:00Z";
  c.device_id = "SIM-0001";
  c.x0_mm = 0, c.y0_mm = 10, c.step_x_mm = 5, c.step_y_mm = 10, c.nx = 3, c.ny = 2;
  c.z_error_mm = {0.001, 0.002, 0.004, 0.003, 0.000, -0.002};
  c.u_mm = {1e-4, 2e-4, 1e-4, 1e-4, 3e-4, 1e-4};
  c.plane_mm[0] = 5.001, c.plane_mm[1] = 2e-4, c.plane_mm[2] = -1e-4;
  return c;
}

std::string refusal(const std::string& text) {
  try {
    calibration_from_json(text, "table.cal.json");
  } catch (const CalibrationError& error) {
    return error.what();
  }
  return "";
}

}  // namespace

TEST_GROUP(TableCalibration){};

TEST(TableCalibration, WrittenAndReadBackItCorrectsTheSameWay) {
  const TableCalibration c = three_by_two();
  const TableCalibration back = calibration_from_json(calibration_to_json(c), "table.cal.json");
  STRCMP_EQUAL("2026-11-26T05:00:00Z", back.created_utc.c_str());
  LONGS_EQUAL(3, back.nx);
  for (int k = 0; k < 3; ++k) DOUBLES_EQUAL(c.plane_mm[k], back.plane_mm[k], 0);
  for (double x : {0.0, 2.5, 7.0, 10.0})
    for (double y : {10.0, 13.0, 20.0}) DOUBLES_EQUAL(c.z_error_at(x, y), back.z_error_at(x, y), 1e-15);
}

TEST(TableCalibration, BetweenNodesTheErrorIsBilinearAndAtANodeItIsTheNodes) {
  const TableCalibration c = three_by_two();
  DOUBLES_EQUAL(0.002, c.z_error_at(5, 10), 1e-15);
  DOUBLES_EQUAL(0.5 * (0.001 + 0.002), c.z_error_at(2.5, 10), 1e-15);
  DOUBLES_EQUAL(0.25 * (0.001 + 0.002 + 0.003 + 0.000), c.z_error_at(2.5, 15), 1e-15);
  DOUBLES_EQUAL(3e-4, c.u_at(2.5, 15), 1e-15);  // the largest of the cell's nodes
}

TEST(TableCalibration, APointOutsideTheCalibratedTravelIsAnErrorThatNamesIt) {
  PointCloud cloud;
  cloud.points = {{2, 12, 1.0}, {10.5, 12, 1.0}};
  try {
    apply_calibration(three_by_two(), cloud, "part.scan");
    FAIL("a point outside the map was corrected");
  } catch (const CalibrationError& error) {
    STRCMP_CONTAINS("point 2 at (10.500, 12.000) mm lies outside the calibrated travel x 0.000..10.000", error.what());
  }
  DOUBLES_EQUAL(1.0, cloud.points[0].z, 0);  // nothing corrected when one point cannot be
}

TEST(TableCalibration, EachPointLosesTheTravelsErrorAndItsSigmaGainsTheMapsUncertainty) {
  PointCloud cloud;
  cloud.points = {{5, 10, 1.0}};
  cloud.sigma = std::vector<double>{4e-4};
  apply_calibration(three_by_two(), cloud, "part.scan");
  DOUBLES_EQUAL(1.0 - 0.002, cloud.points[0].z, 1e-15);
  DOUBLES_EQUAL(std::hypot(4e-4, 3e-4), (*cloud.sigma)[0], 1e-15);  // (5, 10)'s cell reaches the 3e-4 node
}

// The gauge's lean shears a point by its own corrected height: x + z sin(tx), y + z sin(ty), and
// z cos(tilt); the file then says version 2, and a version-1 file that claims a tilt is refused.
TEST(TableCalibration, AGaugeTiltMovesEachPointByItsHeightAndTheFileSaysVersionTwo) {
  TableCalibration c = three_by_two();
  c.has_gauge_tilt = true;
  c.gauge_tilt_x_urad = 3000, c.gauge_tilt_y_urad = -2000, c.u_gauge_tilt_x_urad = 40, c.u_gauge_tilt_y_urad = 41;
  c.sphere_diameter_mm = 25.4, c.sphere_points = 1200, c.sphere_rms_mm = 3e-4;
  const std::string json = calibration_to_json(c);
  STRCMP_CONTAINS("\"version\": 2", json.c_str());
  STRCMP_CONTAINS("\"version\": 1", calibration_to_json(three_by_two()).c_str());  // no tilt: readable as before
  const TableCalibration back = calibration_from_json(json, "table.cal.json");
  CHECK(back.has_gauge_tilt);
  DOUBLES_EQUAL(3000, back.gauge_tilt_x_urad, 0);
  DOUBLES_EQUAL(41, back.u_gauge_tilt_y_urad, 0);
  DOUBLES_EQUAL(25.4, back.sphere_diameter_mm, 0);
  PointCloud cloud;
  cloud.points = {{5, 10, 10.002}};  // the map's 2 um there comes out first: 10 mm high
  apply_calibration(back, cloud, "part.scan");
  const double sx = std::sin(3e-3), sy = std::sin(-2e-3);
  DOUBLES_EQUAL(5 + 10 * sx, cloud.points[0].x, 1e-12);  // 30 um towards +x
  DOUBLES_EQUAL(10 + 10 * sy, cloud.points[0].y, 1e-12);
  DOUBLES_EQUAL(10 * std::sqrt(1 - sx * sx - sy * sy), cloud.points[0].z, 1e-12);
  std::string old = json;
  old.replace(old.find("\"version\": 2"), 12, "\"version\": 1");
  STRCMP_CONTAINS("a gauge tilt in a version 1 file", refusal(old).c_str());
  std::string far = json;
  const size_t at = far.find("\"tilt_x_urad\": 3000");
  far.replace(at, far.find(',', at) - at, "\"tilt_x_urad\": 9e4");
  STRCMP_CONTAINS("a tilt beyond 50000 urad", refusal(far).c_str());
}

// The gauge's scale divides each corrected height by (1 + scale) and widens its sigma by the
// height times the scale's u; a version-1 file that claims a scale is refused.
TEST(TableCalibration, AGaugeScaleRescalesEachHeightAndWidensItsSigma) {
  TableCalibration c = three_by_two();
  c.has_gauge_scale = true;
  c.gauge_scale_ppm = 400, c.u_gauge_scale_ppm = 30, c.scale_steps = 6;
  const std::string json = calibration_to_json(c);
  STRCMP_CONTAINS("\"version\": 2", json.c_str());
  const TableCalibration back = calibration_from_json(json, "table.cal.json");
  CHECK(back.has_gauge_scale);
  DOUBLES_EQUAL(400, back.gauge_scale_ppm, 0);
  PointCloud cloud;
  cloud.points = {{5, 10, 10.002}};  // the map's 2 um there comes out first
  cloud.sigma = std::vector<double>{4e-4};
  apply_calibration(back, cloud, "part.scan");
  DOUBLES_EQUAL(10 / 1.0004, cloud.points[0].z, 1e-12);
  DOUBLES_EQUAL(std::sqrt(4e-4 * 4e-4 + 3e-4 * 3e-4 + std::pow(10 / 1.0004 * 30e-6, 2)), (*cloud.sigma)[0], 1e-12);  // the map u is 3e-4 there
  std::string old = json;
  old.replace(old.find("\"version\": 2"), 12, "\"version\": 1");
  STRCMP_CONTAINS("a gauge scale in a version 1 file", refusal(old).c_str());
}

TEST(TableCalibration, AFileWithAnythingWrongIsRefusedWithWhat) {
  const std::string good = calibration_to_json(three_by_two());
  STRCMP_EQUAL("", refusal(good).c_str());
  STRCMP_CONTAINS("not a JSON object", refusal("[1, 2").c_str());
  STRCMP_CONTAINS("not a digitizer table calibration", refusal("{\"format\": \"something else\"}").c_str());
  auto edited = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    const size_t at = text.find(from);
    CHECK(at != std::string::npos);
    return text.replace(at, from.size(), to);
  };
  STRCMP_CONTAINS("version 4", refusal(edited("\"version\": 1", "\"version\": 4")).c_str());
  // Found by the fuzzer: a version no integer holds.
  STRCMP_CONTAINS("version 1e+300", refusal(edited("\"version\": 1", "\"version\": 1e300")).c_str());
  STRCMP_CONTAINS("z_error_mm must hold nx * ny = 8", refusal(edited("\"nx\": 3", "\"nx\": 4")).c_str());
  STRCMP_CONTAINS("grid steps must be positive", refusal(edited("\"step_x_mm\": 5.0", "\"step_x_mm\": 0")).c_str());
  STRCMP_CONTAINS("u_mm[4] is not a finite number >= 0", refusal(edited("0.0003", "-0.0003")).c_str());
  STRCMP_CONTAINS("z_error_mm[0] is not a finite number within 10 mm", refusal(edited("0.001,", "1e6,")).c_str());
  STRCMP_CONTAINS("the grid lies beyond 10 m", refusal(edited("\"x0_mm\": 0.0", "\"x0_mm\": 1e9")).c_str());
  STRCMP_CONTAINS("grid.x0_mm is missing", refusal(edited("\"x0_mm\"", "\"x_zero\"")).c_str());
}

// A scan file keeps its raw points; the calibration record corrects them when read, and a later
// record (a newer calibration) replaces an earlier one.
TEST(TableCalibration, AScanFilesLastCalibrationRecordCorrectsItsRawPoints) {
  const std::string path = std::string(P_tmpdir) + "/dg_cal_" + std::to_string(getpid()) + ".scan";
  std::remove(path.c_str());
  {
    ScanFileWriter file(path);
    digitizer_Envelope batch = digitizer_Envelope_init_zero;
    batch.which_body = digitizer_Envelope_points_tag;
    digitizer_PointBatch& b = batch.body.points;
    b.first_seq = 0;
    b.x0_nm = 5000000, b.y0_nm = 10000000, b.z0_nm = 1000000;
    b.dx_nm_count = b.dy_nm_count = b.dz_nm_count = b.dt_us_count = 1;
    file.append(batch);
    file.append_calibration(calibration_to_json(three_by_two()));
  }
  ScanData data = read_scan_file(path);
  CHECK(data.calibration_json.has_value());
  LONGS_EQUAL(1000000, data.points.at(0).z_nm);  // raw in the file
  correct_by_record(data, nullptr, path);
  LONGS_EQUAL(1000000 - 2000, data.points.at(0).z_nm);
  TableCalibration newer = three_by_two();
  newer.z_error_mm[1] = 0.005;
  {
    ScanFileWriter file = ScanFileWriter::continue_file(path, read_scan_file(path).complete_bytes);
    file.append_calibration(calibration_to_json(newer));
  }
  data = read_scan_file(path);
  correct_by_record(data, nullptr, path);
  LONGS_EQUAL(1000000 - 5000, data.points.at(0).z_nm);
  std::remove(path.c_str());
}

// The screws' periodic error goes into the file whole (version 3), comes back as it went, moves a
// point by its commanded position, and is refused in a file that says an earlier version.
TEST(TableCalibration, TheScrewsPeriodicErrorRoundTripsAndMovesAPointByItsCommandedPlace) {
  TableCalibration c = three_by_two();
  c.lead.measured = true;
  c.lead.lead_mm = 8;
  c.lead.x_sin_um = 3, c.lead.x_cos_um = -1, c.lead.y_sin_um = 0.5, c.lead.y_cos_um = 2;
  c.lead.u_x_um = 0.1, c.lead.u_y_um = 0.2;
  const std::string json = calibration_to_json(c);
  STRCMP_CONTAINS("\"version\": 3", json.c_str());
  const TableCalibration back = calibration_from_json(json, "t.json");
  CHECK(back.lead.measured);
  DOUBLES_EQUAL(-1, back.lead.x_cos_um, 0);
  PointCloud cloud;
  cloud.points = {{2, 12, 0}};  // a quarter and one and a half turns
  apply_calibration(back, cloud, "part.scan");
  DOUBLES_EQUAL(2 + 0.003 + 0.001 * (-1) * (0 - 1), cloud.points[0].x, 1e-9);
  DOUBLES_EQUAL(12 + 0.0005 * 0 + 0.002 * (-1 - 1), cloud.points[0].y, 1e-9);
  DOUBLES_EQUAL(0, back.lead.dx_mm(0), 0);  // nothing at the commanded origin
  std::string old = json;
  old.replace(old.find("\"version\": 3"), 12, "\"version\": 2");
  STRCMP_CONTAINS("periodic error in a version 2 file", refusal(old).c_str());
  std::string bad = json;
  bad.replace(bad.find("\"lead_mm\": 8.0"), 14, "\"lead_mm\": 0.0");
  STRCMP_CONTAINS("lead_screws: a lead outside", refusal(bad).c_str());
}
