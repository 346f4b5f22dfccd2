// ISO 14253-1's decision rule applied point by point, and the part's verdict from the points'.
#include "host/inspect/decision.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dg::host {

const char* verdict_name(Verdict verdict) {
  switch (verdict) {
    case Verdict::kPass: return "pass";
    case Verdict::kFail: return "fail";
    case Verdict::kInconclusive: return "inconclusive";
  }
  return "?";
}

namespace {

bool usable(const ToleranceLimits& limits) {
  return std::isfinite(limits.lower_mm) && std::isfinite(limits.upper_mm) && limits.lower_mm < limits.upper_mm;
}

Verdict verdict_of(size_t fail, size_t inconclusive) {
  return fail > 0 ? Verdict::kFail : inconclusive > 0 ? Verdict::kInconclusive : Verdict::kPass;
}

}  // namespace

Decision decide(const Inspection& inspection, const ToleranceLimits& general, const std::vector<double>& standard_u_mm,
                const std::string& uncertainty_from, const std::vector<ToleranceZone>& zones) {
  if (!usable(general)) throw std::invalid_argument("the tolerance's lower limit must be below its upper limit");
  if (standard_u_mm.size() != inspection.points.size()) throw std::invalid_argument("one uncertainty per point is needed");
  Decision out;
  out.limits = general;
  out.uncertainty_from = uncertainty_from;
  for (const ToleranceZone& z : zones) {
    if (!usable(z.limits)) throw std::invalid_argument("zone " + z.name + ": its lower limit must be below its upper limit");
    if (!(z.x0_mm < z.x1_mm) || !(z.y0_mm < z.y1_mm) || !std::isfinite(z.x1_mm - z.x0_mm) || !std::isfinite(z.y1_mm - z.y0_mm)) {
      throw std::invalid_argument("zone " + z.name + ": its box must have x0 < x1 and y0 < y1");
    }
    out.zones.push_back({z});
  }
  if (!zones.empty()) {
    ToleranceZone elsewhere;
    elsewhere.name = "elsewhere";
    elsewhere.limits = general;
    out.zones.push_back({elsewhere});
  }
  // How far past the limit a point lies (negative: inside), for ordering the worst.
  std::vector<double> excess(inspection.points.size());
  for (size_t i = 0; i < inspection.points.size(); ++i) {
    const double u = standard_u_mm[i];
    if (!std::isfinite(u) || u < 0) throw std::invalid_argument("point " + std::to_string(i + 1) + ": its uncertainty is not a finite number >= 0");
    const double expanded = 2 * u;
    const double d = inspection.points[i].distance;
    size_t zone = zones.size();  // "elsewhere"
    for (size_t k = 0; k < zones.size(); ++k) {
      if (zones[k].contains(inspection.points[i].point.x, inspection.points[i].point.y)) {
        zone = k;
        break;
      }
    }
    const ToleranceLimits& limits = zones.empty() ? general : out.zones[zone].zone.limits;
    // A point beyond the surface's edge has no deviation along a normal: neither conformance nor
    // non-conformance is proven there, whatever its distance to the edge.
    Verdict v = Verdict::kInconclusive;
    if (inspection.points[i].beyond_edge) ++out.beyond_edge;
    else if (d > limits.upper_mm + expanded || d < limits.lower_mm - expanded) v = Verdict::kFail;
    else if (d >= limits.lower_mm + expanded && d <= limits.upper_mm - expanded) v = Verdict::kPass;
    out.points.push_back(v);
    out.expanded_mm.push_back(expanded);
    out.max_expanded_mm = std::max(out.max_expanded_mm, expanded);
    excess[i] = std::max(d - limits.upper_mm, limits.lower_mm - d);
    if (v == Verdict::kPass) ++out.pass;
    else if (v == Verdict::kFail) ++out.fail;
    else ++out.inconclusive;
    if (!zones.empty()) {
      out.zone_of_point.push_back(zone);
      ZoneDecision& z = out.zones[zone];
      (v == Verdict::kPass ? z.pass : v == Verdict::kFail ? z.fail : z.inconclusive)++;
    }
  }
  out.verdict = verdict_of(out.fail, out.inconclusive);
  for (size_t k = 0; k < out.zones.size(); ++k) {
    ZoneDecision& z = out.zones[k];
    if (k < zones.size() && z.pass + z.fail + z.inconclusive == 0) {
      throw std::invalid_argument("zone " + z.zone.name + " holds none of the points: is its box in the nominal's coordinates?");
    }
    z.verdict = verdict_of(z.fail, z.inconclusive);
  }
  std::vector<size_t> order;
  for (size_t i = 0; i < out.points.size(); ++i) {
    if (out.points[i] != Verdict::kPass) order.push_back(i);
  }
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const bool fa = out.points[a] == Verdict::kFail, fb = out.points[b] == Verdict::kFail;
    if (fa != fb) return fa;
    // Points beyond the edge after those over the surface: their distance to the edge is no
    // measure of how far the part is from conforming, and many would hide the ones that are.
    const bool ea = inspection.points[a].beyond_edge, eb = inspection.points[b].beyond_edge;
    if (ea != eb) return eb;
    return excess[a] > excess[b];
  });
  if (order.size() > 10) order.resize(10);
  out.worst = order;
  return out;
}

}  // namespace dg::host
