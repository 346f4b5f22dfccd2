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

// A board with short frames sizes its batches by point_batch_envelope_max: the worst points there
// are (every delta, time step and flag word at its longest varint, the largest ids) never encode
// longer, and the bound is what they take but for fields this test cannot make longer.
TEST(PointBatch, TheEnvelopeBoundHoldsForTheLongestPoints) {
  uint8_t wire[digitizer_Envelope_size];
  for (size_t n = 1; n <= dg::kMaxPointsPerBatch; ++n) {
    digitizer_Envelope e = digitizer_Envelope_init_zero;
    e.id = UINT32_MAX;
    e.which_body = digitizer_Envelope_points_tag;
    dg::point_batch_begin(&e.body.points, UINT32_MAX - 40, 3);
    for (size_t i = 0; i < n; ++i) {
      // x, y and z swing by 2.14e9 nm between points; time steps by 4e9 us; every flag set.
      const int32_t swing = i % 2 ? 1070000000 : -1070000000;
      dg::PointSample p = point(UINT32_MAX - 40 + static_cast<uint32_t>(i), swing, -swing, swing,
                                (uint64_t{1} << 62) + 4000000000ull * i, UINT32_MAX);
      CHECK(dg::point_batch_append(&e.body.points, p) == dg::Status::kOk);
    }
    size_t size = 0;
    CHECK(dg::encode_envelope(e, wire, sizeof(wire), &size) == dg::Status::kOk);
    CHECK(size <= dg::point_batch_envelope_max(n));
    // The slack: the first point's four deltas are zero (16 bytes), the line is 3 (4), the packed
    // arrays' lengths take one byte (5), t0 one byte less than counted, and the body's length one
    // byte while the body is under 128 bytes.
    LONGS_EQUAL(dg::point_batch_envelope_max(n) - (size < 130 ? 27 : 26), size);
  }
}
