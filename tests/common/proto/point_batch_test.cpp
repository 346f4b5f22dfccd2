// Delta-coded point batches: exact round trips and refusal of inconsistent input.
#include "common/proto/point_batch.h"

#include <CppUTest/TestHarness.h>

#include "common/proto/messages.h"

namespace {

dg::PointSample point(uint32_t seq, int32_t x, int32_t y, int32_t z, uint64_t t, uint32_t flags = 0) {
  dg::PointSample p;
  p.seq = seq;
  p.line = 3;
  p.x_nm = x;
  p.y_nm = y;
  p.z_nm = z;
  p.t_us = t;
  p.flags = flags;
  return p;
}

}  // namespace

TEST_GROUP(PointBatch){};

TEST(PointBatch, RoundTripsThroughTheWire) {
  digitizer_Envelope out = digitizer_Envelope_init_zero;
  out.which_body = digitizer_Envelope_points_tag;
  dg::point_batch_begin(&out.body.points, 100, 3);
  const dg::PointSample points[] = {
      point(100, 0, 5000000, 2000000, 10), point(101, 1000000, 5000000, -1500, 170010),
      point(102, 2000000, 5000000, 2000000000, 340010, 1), point(103, -2000000000, 5000000, 0, 340011)};
  for (const auto& p : points) CHECK(dg::point_batch_append(&out.body.points, p) == dg::Status::kOk);
  uint8_t buffer[digitizer_Envelope_size];
  size_t size = 0;
  CHECK(dg::encode_envelope(out, buffer, sizeof(buffer), &size) == dg::Status::kOk);
  digitizer_Envelope in;
  CHECK(dg::decode_envelope(buffer, size, &in) == dg::Status::kOk);
  dg::PointSample back[dg::kMaxPointsPerBatch];
  size_t count = 0;
  CHECK(dg::point_batch_expand(in.body.points, back, &count) == dg::Status::kOk);
  LONGS_EQUAL(4, count);
  for (size_t i = 0; i < count; ++i) {
    LONGS_EQUAL(points[i].seq, back[i].seq);
    LONGS_EQUAL(3, back[i].line);
    LONGS_EQUAL(points[i].x_nm, back[i].x_nm);
    LONGS_EQUAL(points[i].y_nm, back[i].y_nm);
    LONGS_EQUAL(points[i].z_nm, back[i].z_nm);
    CHECK(points[i].t_us == back[i].t_us);
    LONGS_EQUAL(points[i].flags, back[i].flags);
  }
}

TEST(PointBatch, KeepsAGridPointSmall) {
  digitizer_Envelope out = digitizer_Envelope_init_zero;
  out.which_body = digitizer_Envelope_points_tag;
  dg::point_batch_begin(&out.body.points, 1, 3);
  for (uint32_t i = 0; i < dg::kMaxPointsPerBatch; ++i) {
    const int32_t z = 5000000 + static_cast<int32_t>(i) * 1234;
    CHECK(dg::point_batch_append(&out.body.points,
                                 point(1 + i, static_cast<int32_t>(i) * 1000000, 7000000, z, 170000ull * i)) ==
          dg::Status::kOk);
  }
  uint8_t buffer[digitizer_Envelope_size];
  size_t size = 0;
  CHECK(dg::encode_envelope(out, buffer, sizeof(buffer), &size) == dg::Status::kOk);
  // 1 mm steps, small z changes: well under 12 bytes a point before framing.
  CHECK(size < 12 * dg::kMaxPointsPerBatch);
}

TEST(PointBatch, RefusesAGapOrAnotherLine) {
  digitizer_PointBatch batch;
  dg::point_batch_begin(&batch, 10, 3);
  CHECK(dg::point_batch_append(&batch, point(10, 0, 0, 0, 0)) == dg::Status::kOk);
  CHECK(dg::point_batch_append(&batch, point(12, 0, 0, 0, 0)) == dg::Status::kInvalidArgument);
  dg::PointSample other = point(11, 0, 0, 0, 0);
  other.line = 4;
  CHECK(dg::point_batch_append(&batch, other) == dg::Status::kInvalidArgument);
}

TEST(PointBatch, RefusesWhenFull) {
  digitizer_PointBatch batch;
  dg::point_batch_begin(&batch, 0, 3);
  for (uint32_t i = 0; i < dg::kMaxPointsPerBatch; ++i) {
    CHECK(dg::point_batch_append(&batch, point(i, 0, 0, 0, i)) == dg::Status::kOk);
  }
  CHECK(dg::point_batch_append(&batch, point(dg::kMaxPointsPerBatch, 0, 0, 0, 99)) ==
        dg::Status::kOverflow);
}

TEST(PointBatch, ExpandRejectsArraysOfDifferentLengths) {
  digitizer_PointBatch batch;
  dg::point_batch_begin(&batch, 0, 3);
  CHECK(dg::point_batch_append(&batch, point(0, 0, 0, 0, 0)) == dg::Status::kOk);
  batch.dz_nm_count = 0;
  dg::PointSample out[dg::kMaxPointsPerBatch];
  size_t count = 0;
  CHECK(dg::point_batch_expand(batch, out, &count) == dg::Status::kBadEncoding);
}

TEST(PointBatch, ExpandRejectsCoordinatesThatOverflow) {
  digitizer_PointBatch batch;
  dg::point_batch_begin(&batch, 0, 3);
  CHECK(dg::point_batch_append(&batch, point(0, 2147483000, 0, 0, 0)) == dg::Status::kOk);
  CHECK(dg::point_batch_append(&batch, point(1, 2147483000, 0, 0, 0)) == dg::Status::kOk);
  batch.dx_nm[1] = 10000;  // as a hostile or damaged sender might
  dg::PointSample out[dg::kMaxPointsPerBatch];
  size_t count = 0;
  CHECK(dg::point_batch_expand(batch, out, &count) == dg::Status::kBadEncoding);
}
