// Pass, fail or inconclusive: a profile tolerance decided with the measurement's uncertainty
// (ISO 14253-1's decision rule for proving conformance or non-conformance).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "host/inspect/inspect.h"

namespace dg::host {

enum class Verdict { kPass, kFail, kInconclusive };
const char* verdict_name(Verdict verdict);  // "pass", "fail", "inconclusive"

struct ToleranceLimits {
  double lower_mm = 0, upper_mm = 0;  // the signed deviation's limits, lower < upper
};

struct Decision {
  ToleranceLimits limits;
  Verdict verdict = Verdict::kPass;  // fail if any point fails, else inconclusive if any is, else pass
  size_t pass = 0, fail = 0, inconclusive = 0;
  std::vector<Verdict> points;        // per point, in the inspection's order
  std::vector<double> expanded_mm;    // U = 2u per point
  double max_expanded_mm = 0;
  std::string uncertainty_from;       // where u came from, for the reader
  // Up to ten points that decide the verdict: those that fail, by how far they pass a limit, then
  // the inconclusive ones, the same way; indices into the inspection's points.
  std::vector<size_t> worst;
};

// Each point's deviation d with its expanded uncertainty U = 2u: pass when
// lower + U <= d <= upper - U (conformance proven), fail when d > upper + U or d < lower - U
// (non-conformance proven), inconclusive between. `standard_u_mm` holds u per point. Throws
// std::invalid_argument for limits that are not finite or not lower < upper, a u that is not
// finite and >= 0, or sizes that differ.
Decision decide(const Inspection& inspection, const ToleranceLimits& limits, const std::vector<double>& standard_u_mm,
                const std::string& uncertainty_from);

}  // namespace dg::host
