// nlohmann::json for the inspection summary; numbers in mm.
#include "host/inspect/inspection_json.h"

#include <nlohmann/json.hpp>

namespace dg::host {

std::string inspection_json_text(const Inspection& r, const std::string& points_file, const std::string& surface_file,
                                 const AlignmentSummary* alignment) {
  nlohmann::json j;
  j["format"] = "digitizer-inspection";
  j["version"] = 1;
  j["units"] = "mm";
  j["points_file"] = points_file;
  j["surface_file"] = surface_file;
  const DistanceStats& s = r.stats;
  j["deviation"] = {{"count", s.count}, {"mean", s.mean},     {"median", s.median}, {"stddev", s.stddev},
                    {"rms", s.rms},     {"max", s.max},       {"min", s.min},       {"max_abs", s.max_abs}};
  nlohmann::json bands = nlohmann::json::array();
  for (const Band& b : r.bands) bands.push_back({{"within_mm", b.limit_mm}, {"count", b.count}, {"share", b.share}});
  j["bands"] = bands;
  if (alignment) {
    const AlignmentSummary& a = *alignment;
    j["alignment"] = {{"rotation", a.rotation},
                      {"translation_mm", {a.translation_mm.x, a.translation_mm.y, a.translation_mm.z}},
                      {"rotation_deg", a.rotation_deg},
                      {"rms_before_mm", a.rms_before_mm},
                      {"rms_after_mm", a.rms_after_mm},
                      {"iterations", a.iterations},
                      {"converged", a.converged}};
  } else {
    j["alignment"] = nullptr;
  }
  return j.dump(1) + "\n";
}

}  // namespace dg::host
