// The device's own fit: what it answers before a scan, with too few points, on a single line, and
// the heights of a surface its Bezier patch and net represent exactly.
#include "firmware/core/device_fit.h"

#include <CppUTest/TestHarness.h>

#include "tests/support/scan_request.h"


namespace {

digitizer_ScanRequest request(int32_t y_max_nm) {
  return dg::test::grid_request(9, 10000000, 50000000, y_max_nm, 1000000, digitizer_ScanPattern_PATTERN_RASTER);
}

// z = 3 mm + x / 20 - y / 50 + x y / 4000 (mm): bilinear, so both models hold it exactly.
int32_t bilinear_nm(int32_t x_nm, int32_t y_nm) {
  const double x = x_nm * 1e-6, y = y_nm * 1e-6;
  return static_cast<int32_t>(1e6 * (3.0 + x / 20 - y / 50 + x * y / 4000));
}

void scan_grid(dg::DeviceFit& fit, int32_t y_max_nm) {
  for (int32_t y = 0; y <= y_max_nm; y += 1000000) {
    for (int32_t x = 10000000; x <= 50000000; x += 1000000) {
      dg::PointSample p;
      p.x_nm = x;
      p.y_nm = y;
      p.z_nm = bilinear_nm(x, y);
      fit.add(p);
    }
  }
}

// The device's bases in double: the Bezier patch, or the 5 x 5 net's uniform cubic spans.
void basis(int side, double u, double (&out)[4], int& first) {
  if (side == 4) {
    dg::fit::bernstein(3, u, out);
    first = 0;
    return;
  }
  first = u >= 1.0 ? side - 4 : static_cast<int>(u * (side - 3));
  dg::fit::uniform_cubic_basis(u * (side - 3) - first, out);
}

digitizer_FitStatus status_of(dg::DeviceFit& fit, digitizer_DeviceFitModel model) {
  digitizer_FitResult r;
  fit.result(model, true, &r);
  return r.status;
}

}  // namespace

TEST_GROUP(DeviceFit){};

TEST(DeviceFit, SaysThereIsNoScanBeforeTheFirst) {
  dg::DeviceFit fit;
  LONGS_EQUAL(digitizer_FitStatus_FIT_NO_SCAN, status_of(fit, digitizer_DeviceFitModel_DEVICE_FIT_BEZIER));
}

TEST(DeviceFit, NeedsAsManyPointsAsControlPoints) {
  dg::DeviceFit fit;
  fit.begin(request(30000000));
  dg::PointSample p;
  p.x_nm = 20000000;
  p.y_nm = 1000000;
  fit.add(p);
  digitizer_FitResult r;
  fit.result(digitizer_DeviceFitModel_DEVICE_FIT_NET, false, &r);
  LONGS_EQUAL(digitizer_FitStatus_FIT_TOO_FEW_POINTS, r.status);
  LONGS_EQUAL(1, r.points);
  CHECK_FALSE(r.scan_finished);
}

TEST(DeviceFit, CallsASingleLineUndetermined) {
  dg::DeviceFit fit;
  fit.begin(request(0));
  scan_grid(fit, 0);
  LONGS_EQUAL(digitizer_FitStatus_FIT_UNDETERMINED, status_of(fit, digitizer_DeviceFitModel_DEVICE_FIT_BEZIER));
}

TEST(DeviceFit, ReproducesABilinearPartInBothModels) {
  dg::DeviceFit fit;
  fit.begin(request(30000000));
  scan_grid(fit, 30000000);
  for (auto model : {digitizer_DeviceFitModel_DEVICE_FIT_BEZIER, digitizer_DeviceFitModel_DEVICE_FIT_NET}) {
    digitizer_FitResult r;
    fit.result(model, true, &r);
    LONGS_EQUAL(digitizer_FitStatus_FIT_OK, r.status);
    LONGS_EQUAL(41 * 31, r.points);
    LONGS_EQUAL(0, r.rejected);
    LONGS_EQUAL(9, r.scan_id);
    const int side = model == digitizer_DeviceFitModel_DEVICE_FIT_BEZIER ? 4 : 5;
    LONGS_EQUAL(side, r.side);
    LONGS_EQUAL(side * side, r.z_nm_count);
    // The fitted surface at points across the rectangle, against the part: within 100 nm. The basis
    // values are Q1.15, a relative rounding of 2^-16 of heights up to 5.5 mm here (84 nm).
    for (int a = 0; a <= 8; ++a) {
      for (int b = 0; b <= 6; ++b) {
        const double u = a / 8.0, v = b / 6.0;
        double bu[4], bv[4];
        int first_u = 0, first_v = 0;
        basis(side, u, bu, first_u);
        basis(side, v, bv, first_v);
        double z = 0;
        for (int i = 0; i < 4; ++i) {
          for (int j = 0; j < 4; ++j) z += bu[i] * bv[j] * r.z_nm[(first_u + i) * side + first_v + j];
        }
        const int32_t x = static_cast<int32_t>(10000000 + 40000000 * u), y = static_cast<int32_t>(30000000 * v);
        DOUBLES_EQUAL(bilinear_nm(x, y), z, 100);
      }
    }
  }
}
