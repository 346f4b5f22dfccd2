// nlohmann::json for the inspection summary; numbers in mm.
#include "host/inspect/inspection_json.h"

#include <nlohmann/json.hpp>

namespace dg::host {

std::string inspection_json_text(const Inspection& r, const std::string& points_file, const std::string& surface_file,
                                 const AlignmentSummary* alignment, const Decision* decision, const ReportFields& fields,
                                 const NominalNote* nominal) {
  nlohmann::json j;
  j["format"] = "digitizer-inspection";
  j["version"] = 1;
  j["units"] = "mm";
  j["points_file"] = points_file;
  j["surface_file"] = surface_file;
  for (const auto& [key, value] : {std::pair<const char*, const std::string*>{"part", &fields.part},
                                   {"serial", &fields.serial},
                                   {"operator", &fields.operator_name},
                                   {"company", &fields.company}}) {
    if (!value->empty()) j[key] = *value;
  }
  // null: the surface is a fit of these points, not a nominal.
  j["nominal"] = nominal ? nlohmann::json{{"summary", nominal->summary},
                                          {"points_measured_on_mesh", nominal->measured_on_mesh},
                                          {"mesh_deflection_mm", nominal->mesh_deflection_mm}}
                         : nlohmann::json(nullptr);
  const DistanceStats& s = r.stats;
  j["deviation"] = {{"count", s.count}, {"mean", s.mean},     {"median", s.median}, {"stddev", s.stddev},
                    {"rms", s.rms},     {"max", s.max},       {"min", s.min},       {"max_abs", s.max_abs}};
  nlohmann::json bands = nlohmann::json::array();
  for (const Band& b : r.bands) bands.push_back({{"within_mm", b.limit_mm}, {"count", b.count}, {"share", b.share}});
  j["bands"] = bands;
  // Points whose closest point is on the surface's edge and off to its side (PointDeviation): in
  // "points", not in "deviation" or "bands", which are of the points over the surface.
  j["points"] = r.points.size();
  j["beyond_edge"] = r.beyond_edge;
  if (alignment) {
    const AlignmentSummary& a = *alignment;
    j["alignment"] = {{"rotation", a.rotation},
                      {"translation_mm", {a.translation_mm.x, a.translation_mm.y, a.translation_mm.z}},
                      {"rotation_deg", a.rotation_deg},
                      {"rms_before_mm", a.rms_before_mm},
                      {"rms_after_mm", a.rms_after_mm},
                      {"iterations", a.iterations},
                      {"converged", a.converged},
                      {"points_left_out", a.left_out},
                      {"points_beyond_edge", a.beyond_edge},
                      {"freedoms_held", a.held},
                      {"method", a.datums.empty() ? "best fit" : "datums"}};
    if (!a.datums.empty()) {
      nlohmann::json datums = nlohmann::json::array();
      for (const DatumSummary& d : a.datums) {
        datums.push_back({{"name", d.name},
                          {"box_mm", {{d.x0_mm, d.x1_mm}, {d.y0_mm, d.y1_mm}}},
                          {"points", d.points},
                          {"fixes", d.fixes},
                          {"rms_after_mm", d.rms_after_mm}});
      }
      j["alignment"]["datums"] = datums;
    }
  } else {
    j["alignment"] = nullptr;
  }
  if (decision) {
    const Decision& d = *decision;
    nlohmann::json worst = nlohmann::json::array();
    for (size_t i : d.worst) {
      const PointDeviation& p = r.points[i];
      worst.push_back({{"point", i + 1},
                       {"x", p.point.x},
                       {"y", p.point.y},
                       {"z", p.point.z},
                       {"deviation", p.distance},
                       {"expanded_uncertainty", d.expanded_mm[i]},
                       {"verdict", verdict_name(d.points[i])},
                       {"beyond_edge", p.beyond_edge}});
      if (!d.zones.empty()) worst.back()["zone"] = d.zones[d.zone_of_point[i]].zone.name;
    }
    // Each zone with its box and limits and its own counts; the last, "elsewhere", has no box.
    nlohmann::json zones = nlohmann::json::array();
    for (size_t k = 0; k < d.zones.size(); ++k) {
      const ZoneDecision& z = d.zones[k];
      nlohmann::json zone = {{"name", z.zone.name},         {"lower_limit", z.zone.limits.lower_mm},
                             {"upper_limit", z.zone.limits.upper_mm}, {"verdict", verdict_name(z.verdict)},
                             {"pass", z.pass},              {"fail", z.fail},
                             {"inconclusive", z.inconclusive}};
      if (k + 1 < d.zones.size()) zone["box_mm"] = {{z.zone.x0_mm, z.zone.x1_mm}, {z.zone.y0_mm, z.zone.y1_mm}};
      zones.push_back(zone);
    }
    j["decision"] = {{"rule", "ISO 14253-1"},
                     {"lower_limit", d.limits.lower_mm},
                     {"upper_limit", d.limits.upper_mm},
                     {"verdict", verdict_name(d.verdict)},
                     {"pass", d.pass},
                     {"fail", d.fail},
                     {"inconclusive", d.inconclusive},
                     {"inconclusive_beyond_edge", d.beyond_edge},
                     {"coverage_factor", 2},
                     {"max_expanded_uncertainty", d.max_expanded_mm},
                     {"uncertainty_from", d.uncertainty_from},
                     {"worst", worst},
                     {"zones", zones}};
  } else {
    j["decision"] = nullptr;
  }
  return j.dump(1) + "\n";
}

}  // namespace dg::host
