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

// A region of the part with a tolerance of its own (a drawing's tighter profile on a sealing face,
// say): the points whose x and y, in the nominal's coordinates, lie in the box.
struct ToleranceZone {
  std::string name;
  double x0_mm = 0, x1_mm = 0, y0_mm = 0, y1_mm = 0;
  ToleranceLimits limits;
  bool contains(double x, double y) const { return x >= x0_mm && x <= x1_mm && y >= y0_mm && y <= y1_mm; }
};

// A zone's points decided: its own counts and verdict.
struct ZoneDecision {
  ToleranceZone zone;
  size_t pass = 0, fail = 0, inconclusive = 0;
  Verdict verdict = Verdict::kPass;  // of no points: pass, with all counts 0
};

struct Decision {
  ToleranceLimits limits;             // the general tolerance: points in no zone
  Verdict verdict = Verdict::kPass;  // fail if any point fails, else inconclusive if any is, else pass
  size_t pass = 0, fail = 0, inconclusive = 0;
  size_t beyond_edge = 0;             // of the inconclusive: points beyond the surface's edge
  std::vector<Verdict> points;        // per point, in the inspection's order
  std::vector<double> expanded_mm;    // U = 2u per point
  double max_expanded_mm = 0;
  std::string uncertainty_from;       // where u came from, for the reader
  // Up to ten points that decide the verdict: those that fail, by how far they pass a limit, then
  // the inconclusive ones, the same way, those beyond the surface's edge last; indices into the
  // inspection's points.
  std::vector<size_t> worst;
  // With zones: one per zone, in the order given, then "elsewhere" (the general tolerance's points);
  // zone_of_point holds each point's index into it. Empty without zones.
  std::vector<ZoneDecision> zones;
  std::vector<size_t> zone_of_point;
};

// Each point's deviation d with its expanded uncertainty U = 2u: pass when
// lower + U <= d <= upper - U (conformance proven), fail when d > upper + U or d < lower - U
// (non-conformance proven), inconclusive between, and inconclusive for a point beyond the
// surface's edge (PointDeviation::beyond_edge). `standard_u_mm` holds u per point. Throws
// std::invalid_argument for limits that are not finite or not lower < upper, a u that is not
// finite and >= 0, or sizes that differ. A point in one or more `zones` is decided by the first
// that holds it, with that zone's limits; the rest by `limits`. A zone with a bad box or limits, or
// that holds no point, throws, naming it (a misplaced zone would otherwise pass unnoticed).
Decision decide(const Inspection& inspection, const ToleranceLimits& limits, const std::vector<double>& standard_u_mm,
                const std::string& uncertainty_from, const std::vector<ToleranceZone>& zones = {});

}  // namespace dg::host
