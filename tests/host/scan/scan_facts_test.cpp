// A scan's record in words: the reading settings, the repeatability, and a plain statement that no
// calibration was applied.
#include "host/scan/scan_facts.h"
#include "host/scan/table_calibration.h"

#include <CppUTest/TestHarness.h>

#include <cstring>

using namespace dg::host;

namespace {

bool any_contains(const std::vector<std::string>& lines, const char* text) {
  for (const std::string& line : lines) {
    if (line.find(text) != std::string::npos) return true;
  }
  return false;
}

}  // namespace

TEST_GROUP(ScanFacts){};

TEST(ScanFacts, NameTheReadingSettingsTheRepeatabilityAndThatNoCalibrationWasApplied) {
  ScanData data;
  digitizer_ScanRequest request = digitizer_ScanRequest_init_zero;
  request.x.max_nm = 40000000;
  request.y.max_nm = 30000000;
  request.step_x_nm = request.step_y_nm = 1000000;
  request.feed_um_s = 10000;
  request.samples_per_point = 3;
  request.median = true;
  request.settle_ms = 50;
  request.approach_nm = 500000;
  data.request = request;
  digitizer_Repeatability repeatability = digitizer_Repeatability_init_zero;
  repeatability.count = 30;
  repeatability.stddev_nm = 1250;
  repeatability.x_nm = 20000000;
  data.repeatability = repeatability;
  const std::vector<std::string> facts = scan_facts(data);
  CHECK(any_contains(facts, "grid x 0.000..40.000 mm, y 0.000..30.000 mm, steps 1.000 x 1.000 mm"));
  CHECK(any_contains(facts, "read with feed 10.00 mm/s, 3 samples per point (median), settle 50 ms, approach 0.500 mm"));
  CHECK(any_contains(facts, "s = 1.25 um over 30 readings at (20.000, 0.000) mm"));
  CHECK(any_contains(facts, "calibration: none"));
  CHECK(any_contains(facts, "0 points in 0 lines"));
}

TEST(ScanFacts, SayWhenRepeatabilityWasNotMeasured) {
  const std::vector<std::string> facts = scan_facts(ScanData{});
  CHECK(any_contains(facts, "repeatability: not measured"));
  CHECK(any_contains(facts, "calibration: none"));
}

TEST(ScanFacts, NameTheCalibrationThatCorrectsThePointsAndWhatItLeavesOut) {
  ScanData data;
  TableCalibration c;
  c.created_utc = "2026-11-26T05:00:00Z";
  c.device_id = "SIM-0001";
  c.artefact_flatness_mm = 0.001;
  c.x0_mm = 0, c.y0_mm = 0, c.step_x_mm = 50, c.step_y_mm = 50, c.nx = 3, c.ny = 3;
  c.z_error_mm.assign(9, 0.0);
  c.u_mm.assign(9, 1e-4);
  data.calibration_json = calibration_to_json(c);
  std::vector<std::string> facts = scan_facts(data);
  CHECK(any_contains(facts, "calibration: the table's travel height error, measured on a flat (flatness 0.0010 mm) on "
                            "2026-11-26T05:00:00Z with SIM-0001, over x 0.000..100.000, y 0.000..100.000 mm; squareness "
                            "and scale not compensated"));
  c.has_axes = true;
  c.balls = 9;
  c.scale_x_ppm = 198, c.u_scale_x_ppm = 4.3, c.scale_y_ppm = -146.6, c.u_scale_y_ppm = 4.3, c.squareness_urad = 493.3, c.u_squareness_urad = 4.3;
  data.calibration_json = calibration_to_json(c);
  facts = scan_facts(data);
  CHECK(any_contains(facts, "the axes from a ball plate (9 balls): scale x +198.0 ppm (u 4.3), y -146.6 ppm (u 4.3), squareness "
                            "+493.3 urad (u 4.3)"));
  data.calibration_json = "{}";
  facts = scan_facts(data);
  CHECK(any_contains(facts, "calibration: a record that cannot be used"));
}
