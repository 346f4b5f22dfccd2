// The device's fit end to end: the firmware on the simulated board fits while it scans, the host
// pulls the result over the link, and it matches the host's double-precision fit of the same points.
#include <CppUTest/TestHarness.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "host/device/capture.h"
#include "host/device/pull_fit.h"
#include "host/scan/point_reader.h"
#include "host/scan/scan_file.h"
#include "host/fit/bspline_fit.h"
#include "host/fit/device_fit_surface.h"
#include "host/fit/fit_error.h"
#include "host/transport/transport.h"
#include "tests/support/scan_request.h"

namespace {

digitizer_ScanRequest grid_scan() {
  return dg::test::grid_request(21, 0, 40000000, 30000000, 1000000, digitizer_ScanPattern_PATTERN_SERPENTINE);
}

double worst_difference(const dg::host::BSplineSurface& a, const dg::host::BSplineSurface& b) {
  double worst = 0;
  for (int i = 0; i <= 40; ++i) {
    for (int j = 0; j <= 30; ++j) {
      const double u = i / 40.0, v = j / 30.0;
      worst = std::fmax(worst, std::fabs(a.evaluate(u, v).z - b.evaluate(u, v).z));
    }
  }
  return worst;
}

}  // namespace

TEST_GROUP(SimDeviceFit){};

TEST(SimDeviceFit, PulledPatchMatchesTheHostFitOfTheSamePointsWithinOneMicrometre) {
  const std::string path = std::string(P_tmpdir) + "/dg_device_fit_" + std::to_string(getpid()) + ".scan";
  auto transport = dg::host::open_transport("sim:seed=5,part=canister");
  dg::host::Session session(*transport);
  const digitizer_Hello hello = session.hello(5000);
  {
    dg::host::ScanFileWriter file(path);
    dg::host::capture_scan(session, hello, grid_scan(), file, dg::host::CaptureOptions{});
  }
  const digitizer_FitResult pulled = dg::host::pull_fit(session, hello, digitizer_DeviceFitModel_DEVICE_FIT_BEZIER, 5000);
  LONGS_EQUAL(digitizer_FitStatus_FIT_OK, pulled.status);
  CHECK(pulled.scan_finished);
  LONGS_EQUAL(21, pulled.scan_id);
  LONGS_EQUAL(41 * 31, pulled.points);
  const dg::host::FittedSurface device = dg::host::surface_from_device_fit(pulled, "device");

  const dg::host::PointCloud cloud = dg::host::read_points(path);
  std::remove(path.c_str());
  dg::host::LsqSpec spec;
  spec.knots_u = spec.knots_v = dg::host::clamped_uniform_knots(4, 3);
  const dg::host::BSplineSurface host = dg::host::fit_least_squares(
      cloud.points, dg::host::parameterize(cloud, dg::host::Parameterization::kTableXy), nullptr, spec);
  CHECK(worst_difference(device.surface, host) < 0.001);
  // The control points' x and y are where the host puts a height field's: the Greville abscissae.
  for (size_t k = 0; k < host.control.size(); ++k) {
    DOUBLES_EQUAL(host.control[k].x, device.surface.control[k].x, 1e-9);
    DOUBLES_EQUAL(host.control[k].y, device.surface.control[k].y, 1e-9);
  }
}

TEST(SimDeviceFit, AFreshDeviceHasNoFitToPull) {
  auto transport = dg::host::open_transport("sim:");
  dg::host::Session session(*transport);
  const digitizer_Hello hello = session.hello(5000);
  const digitizer_FitResult pulled = dg::host::pull_fit(session, hello, digitizer_DeviceFitModel_DEVICE_FIT_NET, 5000);
  LONGS_EQUAL(digitizer_FitStatus_FIT_NO_SCAN, pulled.status);
  CHECK_THROWS(dg::host::FitError, dg::host::surface_from_device_fit(pulled, "device"));
}
