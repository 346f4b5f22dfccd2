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

Decision decide(const Inspection& inspection, const ToleranceLimits& limits, const std::vector<double>& standard_u_mm,
                const std::string& uncertainty_from) {
  if (!std::isfinite(limits.lower_mm) || !std::isfinite(limits.upper_mm) || !(limits.lower_mm < limits.upper_mm)) {
    throw std::invalid_argument("the tolerance's lower limit must be below its upper limit");
  }
  if (standard_u_mm.size() != inspection.points.size()) throw std::invalid_argument("one uncertainty per point is needed");
  Decision out;
  out.limits = limits;
  out.uncertainty_from = uncertainty_from;
  // How far past the limit a point lies (negative: inside), for ordering the worst.
  std::vector<double> excess(inspection.points.size());
  for (size_t i = 0; i < inspection.points.size(); ++i) {
    const double u = standard_u_mm[i];
    if (!std::isfinite(u) || u < 0) throw std::invalid_argument("point " + std::to_string(i + 1) + ": its uncertainty is not a finite number >= 0");
    const double expanded = 2 * u;
    const double d = inspection.points[i].distance;
    Verdict v = Verdict::kInconclusive;
    if (d > limits.upper_mm + expanded || d < limits.lower_mm - expanded) v = Verdict::kFail;
    else if (d >= limits.lower_mm + expanded && d <= limits.upper_mm - expanded) v = Verdict::kPass;
    out.points.push_back(v);
    out.expanded_mm.push_back(expanded);
    out.max_expanded_mm = std::max(out.max_expanded_mm, expanded);
    excess[i] = std::max(d - limits.upper_mm, limits.lower_mm - d);
    if (v == Verdict::kPass) ++out.pass;
    else if (v == Verdict::kFail) ++out.fail;
    else ++out.inconclusive;
  }
  out.verdict = out.fail > 0 ? Verdict::kFail : out.inconclusive > 0 ? Verdict::kInconclusive : Verdict::kPass;
  std::vector<size_t> order;
  for (size_t i = 0; i < out.points.size(); ++i) {
    if (out.points[i] != Verdict::kPass) order.push_back(i);
  }
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const bool fa = out.points[a] == Verdict::kFail, fb = out.points[b] == Verdict::kFail;
    if (fa != fb) return fa;
    return excess[a] > excess[b];
  });
  if (order.size() > 10) order.resize(10);
  out.worst = order;
  return out;
}

}  // namespace dg::host
