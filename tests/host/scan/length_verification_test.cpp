// Ball-to-ball lengths against their certified values: exact on an ideal plate, the scale error
// seen as an error growing with length, and E_MPE = A + L/K applied per length.
#include <CppUTest/TestHarness.h>

#include <cmath>

#include "host/scan/ball_plate_calibration.h"
#include "host/scan/length_verification.h"
#include "hw/sim/parts.h"
#include "tests/support/ball_plate.h"

using namespace dg::host;

namespace {

std::vector<Point2> certificate() { return dg::test::ball_plate_certificate(); }

// The plate laid at (x0, y0) turned `angle` on a table whose x readings are `scale_ppm` long,
// read without noise on a 0.5 mm grid.
PointCloud placed_plate(double x0, double y0, double angle_deg, double scale_ppm) {
  dg::sim::Part part;
  part.kind = dg::sim::PartKind::kBallPlate;
  part.x0_mm = x0, part.y0_mm = y0, part.angle_deg = angle_deg;
  PointCloud cloud;
  for (double y = 0; y <= 150; y += 0.5)
    for (double x = 0; x <= 150; x += 0.5) cloud.points.push_back({x * (1 + scale_ppm * 1e-6), y, part.height_mm(x, y)});
  return cloud;
}

}  // namespace

TEST_GROUP(LengthVerification){};

TEST(LengthVerification, AnIdealTableMeasuresEveryLengthOfAPlacedPlateWithinAMicrometre) {
  const LengthVerification v = verify_lengths(placed_plate(30, 20, 25, 0), certificate(), 30, 20, 25, PermissibleError{}, 0, "plate");
  LONGS_EQUAL(36, v.lengths.size());
  CHECK(v.worst_error_mm < 1e-3);
  CHECK(v.pass);
}

TEST(LengthVerification, AScaleErrorShowsAsAnErrorThatGrowsWithLengthAndFailsTheLongOnes) {
  // 100 ppm along x: the 70 mm length along x reads 7 um long; E_MPE there is 3 + 70/250 = 3.28 um.
  const LengthVerification v = verify_lengths(placed_plate(5, 5, 0, 100), certificate(), 5, 5, 0, PermissibleError{}, 0, "plate");
  CHECK_FALSE(v.pass);
  for (const MeasuredLength& l : v.lengths) {
    if (l.from == 0 && l.to == 2) DOUBLES_EQUAL(0.007, l.error_mm(), 0.0007);
  }
  const LengthVerification loose = verify_lengths(placed_plate(5, 5, 0, 100), certificate(), 5, 5, 0, PermissibleError{10, 100}, 0, "plate");
  CHECK(loose.pass);
  const LengthVerification long_only = verify_lengths(placed_plate(5, 5, 0, 0), certificate(), 5, 5, 0, PermissibleError{}, 60, "plate");
  for (const MeasuredLength& l : long_only.lengths) CHECK(l.certified_mm >= 60);
}

TEST(LengthVerification, APlateLaidElsewhereThanSaidIsRefusedWithTheBallItCannotFind) {
  try {
    verify_lengths(placed_plate(5, 5, 0, 0), certificate(), 40, 40, 0, PermissibleError{}, 0, "plate");
    FAIL("balls were found where the plate is not");
  } catch (const std::exception& error) {
    STRCMP_CONTAINS("ball 3 (expected at 125.000, 55.000 mm): no ball there", error.what());
  }
}

// Along z: the heights between every two steps against their certified differences, in the
// certificate's sense; a gauge reading 400 ppm long fails the longest of them.
TEST(LengthVerification, StepHeightsAreJudgedBetweenEveryTwoStepsAndAScaleFailsTheLongest) {
  const std::vector<double> certified = {2, 4, 6, 12};
  std::vector<StepLevel> steps(4);
  for (size_t k = 0; k < 4; ++k) steps[k].height_mm = (certified[k] - 1) * 1.0004;
  const PermissibleError mpe{3, 250};
  const LengthVerification v = verify_heights(steps, certified, mpe, 0);
  LONGS_EQUAL(6, v.lengths.size());
  DOUBLES_EQUAL(10.0, v.lengths[2].certified_mm, 1e-12);  // steps 1 and 4
  DOUBLES_EQUAL(0.004, v.lengths[2].error_mm(), 1e-9);
  CHECK_FALSE(v.pass);  // 4 um against 3 + 10/250
  DOUBLES_EQUAL(0.004, v.worst_error_mm, 1e-9);
  LONGS_EQUAL(3, verify_heights(steps, certified, mpe, 5.0).lengths.size());  // 6, 8 and 10 mm only
  std::vector<StepLevel> swapped = steps;
  std::swap(swapped[0].height_mm, swapped[1].height_mm);  // the 2 mm step read 2 mm higher than the 4 mm one
  DOUBLES_EQUAL(-2.0008, verify_heights(swapped, certified, mpe, 0).lengths[0].measured_mm, 1e-9);
}
