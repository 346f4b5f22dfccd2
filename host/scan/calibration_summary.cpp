// The calibration's summary for the device, and its words for a person.
#include "host/scan/calibration_summary.h"

#include <cstdio>
#include <ctime>

#include "common/link/crc32.h"

namespace dg::host {

uint64_t utc_to_unix(const std::string& text) {
  std::tm tm{};
  char zone = 0, extra = 0;
  if (text.size() != 20 || std::sscanf(text.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d%c%c", &tm.tm_year, &tm.tm_mon, &tm.tm_mday,
                                       &tm.tm_hour, &tm.tm_min, &tm.tm_sec, &zone, &extra) != 7 || zone != 'Z') {
    return 0;
  }
  if (tm.tm_year < 1970 || tm.tm_mon < 1 || tm.tm_mon > 12 || tm.tm_mday < 1 || tm.tm_mday > 31 || tm.tm_hour > 23 ||
      tm.tm_min > 59 || tm.tm_sec > 60) {
    return 0;
  }
  tm.tm_year -= 1900, tm.tm_mon -= 1;
  const std::time_t t = timegm(&tm);
  return t > 0 ? static_cast<uint64_t>(t) : 0;
}

std::string unix_to_utc(uint64_t seconds) {
  if (seconds == 0) return "an unknown time";
  const std::time_t t = static_cast<std::time_t>(seconds);
  std::tm tm{};
  if (gmtime_r(&t, &tm) == nullptr) return "an unknown time";
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

digitizer_CalibrationSummary summarize_calibration(const TableCalibration& c, const std::string& file_text) {
  digitizer_CalibrationSummary s = digitizer_CalibrationSummary_init_zero;
  s.version = static_cast<uint32_t>(c.version());
  s.file_crc32 = crc32(reinterpret_cast<const uint8_t*>(file_text.data()), file_text.size());
  s.parts = digitizer_CalibrationPart_CALIBRATED_TRAVEL;
  uint64_t latest = utc_to_unix(c.created_utc);
  auto part = [&](bool present, digitizer_CalibrationPart bit, const std::string& created) {
    if (!present) return;
    s.parts |= bit;
    const uint64_t t = utc_to_unix(created);
    if (t > latest) latest = t;
  };
  part(c.has_axes, digitizer_CalibrationPart_CALIBRATED_AXES, c.axes_created_utc);
  part(c.has_axes && c.straightness.measured, digitizer_CalibrationPart_CALIBRATED_STRAIGHTNESS, c.axes_created_utc);
  part(c.lead.measured, digitizer_CalibrationPart_CALIBRATED_LEAD, c.gauge_created_utc);
  part(c.has_gauge_tilt, digitizer_CalibrationPart_CALIBRATED_GAUGE_TILT, c.gauge_created_utc);
  part(c.has_gauge_scale, digitizer_CalibrationPart_CALIBRATED_GAUGE_SCALE, c.scale_created_utc);
  s.created_unix_s = latest;
  return s;
}

std::string calibration_parts_text(uint32_t parts) {
  static const struct {
    uint32_t bit;
    const char* name;
  } kParts[] = {{digitizer_CalibrationPart_CALIBRATED_TRAVEL, "travel map"},
                {digitizer_CalibrationPart_CALIBRATED_AXES, "axes"},
                {digitizer_CalibrationPart_CALIBRATED_STRAIGHTNESS, "straightness"},
                {digitizer_CalibrationPart_CALIBRATED_LEAD, "lead screws"},
                {digitizer_CalibrationPart_CALIBRATED_GAUGE_TILT, "gauge tilt"},
                {digitizer_CalibrationPart_CALIBRATED_GAUGE_SCALE, "gauge scale"}};
  std::string text;
  for (const auto& p : kParts) {
    if ((parts & p.bit) == 0) continue;
    if (!text.empty()) text += ", ";
    text += p.name;
  }
  return text.empty() ? "nothing" : text;
}

}  // namespace dg::host
