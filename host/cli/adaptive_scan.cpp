// The adaptive scan's rounds: plan from the file's points, measure each run, read again.
#include "host/cli/adaptive_scan.h"

#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

#include "common/proto/scan_grid.h"
#include "host/fit/one_surface_fit.h"
#include "host/scan/point_reader.h"
#include "host/scan/scan_file.h"

namespace dg::host {

std::string adaptive_refusal(const digitizer_ScanRequest& request) {
  if (flies(request)) return "--adaptive refines a stop-and-go grid (not --mode fly)";
  if (request.reference_every_lines > 0) return "--adaptive and --reference-every do not go together (the passes are short)";
  if (request.step_x_nm != request.step_y_nm) return "--adaptive halves one step along both axes: give one --step for both";
  return "";
}

namespace {

SamplingGrid grid_of(const digitizer_ScanRequest& coarse, double min_step_mm) {
  SamplingGrid grid;
  grid.x0_mm = coarse.x.min_nm * 1e-6;
  grid.y0_mm = coarse.y.min_nm * 1e-6;
  grid.x1_mm = coarse.x.max_nm * 1e-6;
  grid.y1_mm = coarse.y.max_nm * 1e-6;
  grid.step_mm = coarse.step_x_nm * 1e-6;
  grid.min_step_mm = min_step_mm > 0 ? min_step_mm : grid.step_mm / 8;
  return grid;
}

// One run as a request of one line (along x) or of one point on each of its lines (along y), read
// as the coarse pass was.
digitizer_ScanRequest run_request(const digitizer_ScanRequest& coarse, const SampleRun& run, double unit_mm, uint32_t scan_id) {
  digitizer_ScanRequest r = coarse;
  r.scan_id = scan_id;
  const double span_mm = (run.count - 1) * run.step_mm;
  const uint32_t step_nm = static_cast<uint32_t>(std::llround((run.count > 1 ? run.step_mm : unit_mm) * 1e6));
  r.x.min_nm = static_cast<int32_t>(std::llround(run.x0_mm * 1e6));
  r.y.min_nm = static_cast<int32_t>(std::llround(run.y0_mm * 1e6));
  r.x.max_nm = static_cast<int32_t>(std::llround((run.x0_mm + (run.along_y ? 0 : span_mm)) * 1e6));
  r.y.max_nm = static_cast<int32_t>(std::llround((run.y0_mm + (run.along_y ? span_mm : 0)) * 1e6));
  r.step_x_nm = run.along_y ? static_cast<uint32_t>(std::llround(unit_mm * 1e6)) : step_nm;
  r.step_y_nm = run.along_y ? step_nm : static_cast<uint32_t>(std::llround(unit_mm * 1e6));
  r.pattern = digitizer_ScanPattern_PATTERN_RASTER;
  r.reference_every_lines = 0;
  return r;
}

}  // namespace

AdaptiveResult refine_scan(Session& session, ScanSink& file, const std::string& path, const digitizer_ScanRequest& coarse,
                           const AdaptiveOptions& adaptive, const CaptureOptions& options) {
  const std::string refusal = adaptive_refusal(coarse);
  if (!refusal.empty()) throw std::invalid_argument(refusal);
  if (!(adaptive.tolerance_mm > 0)) throw std::invalid_argument("--adaptive needs --tolerance MM > 0");
  const SamplingGrid grid = grid_of(coarse, adaptive.min_step_mm);
  std::random_device entropy;
  AdaptiveResult result;
  CaptureOptions quiet_options = options;
  quiet_options.progress = nullptr;  // a pass is a few points: one line a round instead
  for (;;) {
    const ScanData data = read_scan_file(path);
    std::vector<Point3> points;
    points.reserve(data.points.size());
    for (const auto& p : data.points) points.push_back({p.x_nm * 1e-6, p.y_nm * 1e-6, p.z_nm * 1e-6});
    result.last = plan_refinement(points, grid, adaptive.tolerance_mm);
    if (result.last.runs.empty()) {
      // The neighbours predict every point: now the fit, which must also hold between the samples,
      // decides; where it fails, the columns and rows around its failures come next.
      const PointCloud cloud = read_points(path);
      Parameters params;
      Creases creases;
      const ToleranceResult fit = fit_one_surface(cloud, adaptive.tolerance_mm, &params, &creases);
      // The creases' lines first (their knots want lines about them: a point with y NaN names a
      // line across x), then the fit's worst point and its validation's.
      std::vector<Point3> failures;
      for (double u : creases.u) failures.push_back({params.x_min + u * (params.x_max - params.x_min), NAN, 0});
      for (double v : creases.v) failures.push_back({NAN, params.y_min + v * (params.y_max - params.y_min), 0});
      result.fit_kept = fit.kept && fit.validation.passed;
      result.fit_reason = fit.kept ? fit.validation.problem : fit.reason;
      if (result.fit_kept) return result;
      size_t worst = 0;
      for (size_t k = 1; k < fit.distances.size(); ++k) {
        if (std::fabs(fit.distances[k]) > std::fabs(fit.distances[worst])) worst = k;
      }
      if (!fit.distances.empty() && std::fabs(fit.distances[worst]) > adaptive.tolerance_mm) failures.push_back(cloud.points[worst]);
      // The validation's worst places, where it measured any (a fit it could not validate names none).
      if (fit.validation.checked && fit.validation.held_out_max_mm > adaptive.tolerance_mm) failures.push_back(fit.validation.held_out_worst);
      if (fit.validation.checked && fit.validation.range_excess_max_mm > 0) failures.push_back(fit.validation.range_worst);
      result.last = plan_refinement(points, grid, adaptive.tolerance_mm, failures);
      if (result.last.runs.empty()) return result;
    }
    ++result.rounds;
    if (!adaptive.quiet) {
      std::printf("adaptive round %d: a %zu x %zu grid, points predicted up to %.4f mm off (at %.3f, %.3f) beside %zu intervals "
                  "over %.4f mm: %zu new columns, %zu new rows, %zu new points in %zu passes\n",
                  result.rounds, result.last.columns, result.last.rows, result.last.worst_mm, result.last.worst_at.x,
                  result.last.worst_at.y, result.last.intervals_over, adaptive.tolerance_mm, result.last.new_columns,
                  result.last.new_rows, result.last.new_points, result.last.runs.size());
      std::fflush(stdout);
    }
    for (const SampleRun& run : result.last.runs) {
      const digitizer_ScanRequest request = run_request(coarse, run, grid.unit_mm(), (entropy() & 0x7fffffffu) | 1u);
      const CaptureResult pass = capture_pass(session, request, file, quiet_options);
      ++result.passes;
      if (pass.interrupted || pass.done.reason != digitizer_ScanEnd_SCAN_COMPLETED) {
        result.completed = false;
        result.failed = pass;
        return result;
      }
      result.new_points += static_cast<size_t>(run.count);
    }
  }
}

}  // namespace dg::host
