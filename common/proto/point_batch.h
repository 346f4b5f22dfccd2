// Packing measured points into delta-coded PointBatch messages and reading them back.
#pragma once
#include <cstddef>
#include <cstdint>

#include "common/status.h"
#include "digitizer.pb.h"

namespace dg {

// One measured point as both ends see it.
// The 64-bit time comes first so that the fields pack without padding: 32 bytes a point in the
// device's ring rather than 40.
struct PointSample {
  uint64_t t_us = 0;
  uint32_t seq = 0;
  uint32_t line = 0;
  int32_t x_nm = 0;
  int32_t y_nm = 0;
  int32_t z_nm = 0;
  uint32_t flags = 0;
};

constexpr size_t kMaxPointsPerBatch =
    sizeof(digitizer_PointBatch::dx_nm) / sizeof(digitizer_PointBatch::dx_nm[0]);

// The most bytes an Envelope holding a batch of `points` points can take: the request id (tag and a
// 5-byte varint), the body's tag and a 2-byte length; first_seq, line, x0, y0, z0 (a tag and up to
// 5 bytes each) and t0 (a tag and up to 10); five packed arrays (a tag and a 2-byte length each);
// and per point five varints of up to 5 bytes (dx, dy, dz, dt, flags). A board whose frames are
// shorter than the protocol's sends as many points per batch as this lets it.
constexpr size_t point_batch_envelope_max(size_t points) { return 6 + 3 + 5 * 6 + 11 + 5 * 3 + 25 * points; }

// Starts an empty batch for points of one line, the first numbered `first_seq`.
void point_batch_begin(digitizer_PointBatch* batch, uint32_t first_seq, uint32_t line);

// Appends a point. kOverflow when the batch is full; kInvalidArgument when the
// point does not continue the batch (another line or a gap in seq) or its
// deltas do not fit the wire types.
Status point_batch_append(digitizer_PointBatch* batch, const PointSample& point);

size_t point_batch_size(const digitizer_PointBatch& batch);

// Expands a received batch. kBadEncoding if its arrays disagree in length.
// `out` must hold kMaxPointsPerBatch points.
Status point_batch_expand(const digitizer_PointBatch& batch, PointSample* out, size_t* count);

}  // namespace dg
