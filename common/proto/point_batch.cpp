// Delta coding keeps a point on a 1 mm grid at about 8 wire bytes instead of 25.
#include "common/proto/point_batch.h"

namespace dg {
namespace {

bool fits_int32(int64_t v) { return v >= INT32_MIN && v <= INT32_MAX; }

}  // namespace

void point_batch_begin(digitizer_PointBatch* batch, uint32_t first_seq, uint32_t line) {
  *batch = digitizer_PointBatch_init_zero;
  batch->first_seq = first_seq;
  batch->line = line;
}

size_t point_batch_size(const digitizer_PointBatch& batch) { return batch.dx_nm_count; }

Status point_batch_append(digitizer_PointBatch* batch, const PointSample& point) {
  const size_t n = batch->dx_nm_count;
  if (n >= kMaxPointsPerBatch) return Status::kOverflow;
  if (point.line != batch->line || point.seq != batch->first_seq + n) {
    return Status::kInvalidArgument;
  }
  int64_t px = batch->x0_nm, py = batch->y0_nm, pz = batch->z0_nm;
  uint64_t pt = batch->t0_us;
  if (n == 0) {
    batch->x0_nm = point.x_nm;
    batch->y0_nm = point.y_nm;
    batch->z0_nm = point.z_nm;
    batch->t0_us = point.t_us;
    px = point.x_nm;
    py = point.y_nm;
    pz = point.z_nm;
    pt = point.t_us;
  } else {
    for (size_t i = 0; i < n; ++i) {
      px += batch->dx_nm[i];
      py += batch->dy_nm[i];
      pz += batch->dz_nm[i];
      pt += batch->dt_us[i];
    }
  }
  const int64_t dx = static_cast<int64_t>(point.x_nm) - px;
  const int64_t dy = static_cast<int64_t>(point.y_nm) - py;
  const int64_t dz = static_cast<int64_t>(point.z_nm) - pz;
  if (!fits_int32(dx) || !fits_int32(dy) || !fits_int32(dz) || point.t_us < pt ||
      point.t_us - pt > UINT32_MAX) {
    return Status::kInvalidArgument;
  }
  batch->dx_nm[n] = static_cast<int32_t>(dx);
  batch->dy_nm[n] = static_cast<int32_t>(dy);
  batch->dz_nm[n] = static_cast<int32_t>(dz);
  batch->dt_us[n] = static_cast<uint32_t>(point.t_us - pt);
  // Flags are sent only once a point has any, so clean batches carry none.
  if (point.flags != 0 && batch->flags_count == 0) {
    for (size_t i = 0; i < n; ++i) batch->flags[i] = 0;
    batch->flags_count = static_cast<pb_size_t>(n);
  }
  if (batch->flags_count != 0 || point.flags != 0) {
    batch->flags[n] = point.flags;
    batch->flags_count = static_cast<pb_size_t>(n + 1);
  }
  batch->dx_nm_count = batch->dy_nm_count = batch->dz_nm_count = batch->dt_us_count =
      static_cast<pb_size_t>(n + 1);
  return Status::kOk;
}

Status point_batch_expand(const digitizer_PointBatch& batch, PointSample* out, size_t* count) {
  const size_t n = batch.dx_nm_count;
  if (batch.dy_nm_count != n || batch.dz_nm_count != n || batch.dt_us_count != n ||
      (batch.flags_count != 0 && batch.flags_count != n) || n > kMaxPointsPerBatch) {
    return Status::kBadEncoding;
  }
  int64_t x = batch.x0_nm, y = batch.y0_nm, z = batch.z0_nm;
  uint64_t t = batch.t0_us;
  for (size_t i = 0; i < n; ++i) {
    x += batch.dx_nm[i];
    y += batch.dy_nm[i];
    z += batch.dz_nm[i];
    t += batch.dt_us[i];
    if (!fits_int32(x) || !fits_int32(y) || !fits_int32(z)) return Status::kBadEncoding;
    PointSample& p = out[i];
    p.seq = batch.first_seq + static_cast<uint32_t>(i);
    p.line = batch.line;
    p.x_nm = static_cast<int32_t>(x);
    p.y_nm = static_cast<int32_t>(y);
    p.z_nm = static_cast<int32_t>(z);
    p.t_us = t;
    p.flags = batch.flags_count != 0 ? batch.flags[i] : 0;
  }
  *count = n;
  return Status::kOk;
}

}  // namespace dg
