// Feeding scanned points to the fixed-point fits and answering CMD_PULL_FIT.
#include "firmware/core/device_fit.h"

namespace dg {

void DeviceFit::begin(const digitizer_ScanRequest& request) {
  fit::FitRegion region;
  region.x_min_nm = request.x.min_nm;
  region.x_max_nm = request.x.max_nm;
  region.y_min_nm = request.y.min_nm;
  region.y_max_nm = request.y.max_nm;
  moments_.begin(region);
  scan_id_ = request.scan_id;
  started_ = true;
}

void DeviceFit::add(const PointSample& point) {
  // A reference reading repeats the scan's first point to measure drift; it is no new point of
  // the surface.
  // Nor is a reading taken with the plunger off the part (on the fly).
  if (!started_ || (point.flags & (digitizer_PointFlag_POINT_REFERENCE | digitizer_PointFlag_POINT_LIFTED)) != 0) return;
  // A point the fixed-point sums cannot hold is counted as rejected by the fit and reported; the
  // point itself is stored and sent like any other.
  (void)moments_.add(point.x_nm, point.y_nm, point.z_nm);
}

namespace {

template <typename Kind, typename Moments, typename Work>
digitizer_FitStatus solve_into(const Moments& moments, Work& work, digitizer_FitResult* out) {
  constexpr int kSide = Kind::kSide;
  int32_t solved[kSide][kSide];
  const Status status = fit::solve_height_field<Kind>(moments, solved, work);
  out->points = moments.count();
  out->rejected = moments.rejected();
  if (status == Status::kNotReady) {
    return moments.region().valid() ? digitizer_FitStatus_FIT_TOO_FEW_POINTS : digitizer_FitStatus_FIT_UNDETERMINED;
  }
  if (status != Status::kOk) return digitizer_FitStatus_FIT_UNDETERMINED;
  out->side = kSide;
  out->z_nm_count = kSide * kSide;
  for (int i = 0; i < kSide; ++i) {
    for (int j = 0; j < kSide; ++j) {
      out->z_nm[i * kSide + j] = solved[i][j];
    }
  }
  return digitizer_FitStatus_FIT_OK;
}

}  // namespace

void DeviceFit::result(digitizer_DeviceFitModel model, bool scan_finished, digitizer_FitResult* out) {
  *out = digitizer_FitResult_init_zero;
  out->model = model;
  out->scan_finished = scan_finished;
  if (!started_) {
    out->status = digitizer_FitStatus_FIT_NO_SCAN;
    return;
  }
  out->scan_id = scan_id_;
  const fit::FitRegion& region = moments_.region();
  out->has_x = out->has_y = true;
  out->x.min_nm = region.x_min_nm;
  out->x.max_nm = region.x_max_nm;
  out->y.min_nm = region.y_min_nm;
  out->y.max_nm = region.y_max_nm;
  out->status = model == digitizer_DeviceFitModel_DEVICE_FIT_NET
                    ? solve_into<NetKind>(moments_, work_.net, out)
                    : solve_into<BezierKind>(moments_, work_.bezier, out);
}

}  // namespace dg
