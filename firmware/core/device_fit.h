// The surfaces the device fits while it scans: a bicubic Bezier patch and a 5 x 5 cubic net over the
// scanned rectangle, both solved from one set of streamed sums, in fixed point and constant memory
// (common/fit).
#pragma once
#include <cstdint>

#include "common/fit/height_field_fit.h"
#include "common/proto/point_batch.h"
#include "digitizer.pb.h"

namespace dg {

class DeviceFit {
 public:
  static constexpr int kNetSide = 5;
  using Policy = fit::FixedPolicy<15>;
  using BezierKind = fit::BezierBasis;
  using NetKind = fit::UniformCubicBasis<kNetSide>;
  // Each fit on its own (the benchmarks compare them with the shared sums).
  using Bezier = fit::HeightFieldFit<Policy, BezierKind>;
  using Net = fit::HeightFieldFit<Policy, NetKind>;

  // Starts both fits over the request's rectangle; the previous scan's fit is dropped.
  void begin(const digitizer_ScanRequest& request);
  void add(const PointSample& point);
  // Solves `model` from the points so far and fills `out` (the scan may still be running).
  void result(digitizer_DeviceFitModel model, bool scan_finished, digitizer_FitResult* out);

 private:
  bool started_ = false;
  uint32_t scan_id_ = 0;
  // The net's blocks: the patch's one span is made of them too, so both fits read the same sums
  // and a point is summed once.
  fit::BlockMoments<Policy, NetKind::kSpans> moments_;
  // One solve at a time, so the two fits share their scratch memory.
  union Workspace {
    Workspace() : net() {}
    fit::HeightFieldWorkspace<Policy, BezierKind> bezier;
    fit::HeightFieldWorkspace<Policy, NetKind> net;
  } work_;
};

}  // namespace dg
