// The calibration's summary for the device: its time is the latest part's, its parts are what the
// file holds, its CRC is the file's, and times read and print as calibrate writes them.
#include "host/scan/calibration_summary.h"

#include <CppUTest/TestHarness.h>

#include <string>

#include "common/link/crc32.h"

using namespace dg::host;

TEST_GROUP(CalibrationSummary){};

TEST(CalibrationSummary, ReadsAndPrintsTheTimesCalibrateWritesAndRefusesOthers) {
  CHECK(1795000000 == utc_to_unix("2026-11-18T11:06:40Z"));
  STRCMP_EQUAL("2026-11-18T11:06:40Z", unix_to_utc(1795000000).c_str());
  for (const char* bad : {"", "2026-11-18 08:26:40", "2026-13-18T08:26:40Z", "2026-11-18T08:26:40+01", "1969-12-31T23:59:59Z",
                          "2026-11-18T11:06:40Zx"}) {
    CHECK(0 == utc_to_unix(bad));
  }
  STRCMP_EQUAL("an unknown time", unix_to_utc(0).c_str());
}

TEST(CalibrationSummary, SaysTheLatestPartsTimeWhatTheFileHoldsAndItsCrc) {
  TableCalibration c;
  c.created_utc = "2026-11-01T10:00:00Z";
  c.has_axes = true;
  c.axes_created_utc = "2026-11-03T10:00:00Z";
  c.has_gauge_tilt = true;
  c.gauge_created_utc = "2026-11-02T10:00:00Z";
  c.lead.measured = true;
  c.lead.lead_mm = 8;
  const std::string text = "{\"format\": \"digitizer table calibration\"}\n";
  const digitizer_CalibrationSummary s = summarize_calibration(c, text);
  CHECK(utc_to_unix("2026-11-03T10:00:00Z") == s.created_unix_s);
  LONGS_EQUAL(3, s.version);  // the lead came with version 3
  LONGS_EQUAL(dg::crc32(reinterpret_cast<const uint8_t*>(text.data()), text.size()), s.file_crc32);
  STRCMP_EQUAL("travel map, axes, lead screws, gauge tilt", calibration_parts_text(s.parts).c_str());
  STRCMP_EQUAL("nothing", calibration_parts_text(0).c_str());
}
