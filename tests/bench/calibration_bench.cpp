// The table calibration on the simulator: a table with the typical errors (travel 30 um out of flat,
// 500 urad out of square, 200 and -150 ppm of scale, the gauge leaning 3 and -2 mrad and reading
// 400 ppm long), calibrated on a flat, a step gauge, a ball plate and a reference sphere, then
// each part scanned later (another seed) and compared with its true shape, uncorrected and corrected;
// and a drifting gauge stand, its drift removed by reading the first point again every N lines.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "host/cli/calibrate_command.h"
#include "host/cli/scan_command.h"
#include "host/scan/point_reader.h"
#include "host/scan/scan_file.h"
#include "host/scan/table_calibration.h"
#include "hw/sim/parts.h"

int main() {
  using Clock = std::chrono::steady_clock;
  const std::string dir = std::string(P_tmpdir) + "/dg_calibration_bench_" + std::to_string(getpid());
  const std::string cal = dir + ".cal.json";
  const char* machine = "machine=typical,noise_um=1";
  dg::host::CalibrateArgs a;
  a.device = std::string("sim:part=flat,seed=21,") + machine;
  a.output = cal;
  a.force = true;
  a.quiet = true;
  const auto start = Clock::now();
  if (dg::host::run_calibrate(a) != 0) return 1;
  dg::host::CalibrateArgs steps = a;
  steps.artefact = "stepgauge";
  steps.device = std::string("sim:part=stepgauge,seed=26,") + machine;
  steps.certificate = dir + ".steps.csv";
  {
    FILE* f = std::fopen(steps.certificate.c_str(), "w");
    for (int k = 0; k < dg::sim::kSteps; ++k) std::fprintf(f, "%g\n", dg::sim::step_height_mm(k));
    std::fclose(f);
  }
  steps.x = "5.5:40.5", steps.y = "6:24";
  steps.ball_step_mm = 0.5;
  if (dg::host::run_calibrate(steps) != 0) return 1;
  dg::host::CalibrateArgs sphere = a;
  sphere.artefact = "sphere";
  sphere.device = std::string("sim:part=sphere,seed=25,") + machine;
  sphere.diameter_mm = 2 * dg::sim::kSphereRadiusMm;
  sphere.sphere_at = "20,15";
  sphere.ball_step_mm = 0.5;
  sphere.lead_mm = 8;
  if (dg::host::run_calibrate(sphere) != 0) return 1;
  // The plate after the sphere: its balls then lie where the screws really put them.
  dg::host::CalibrateArgs plate = a;
  plate.artefact = "ballplate";
  plate.device = std::string("sim:part=ballplate,seed=23,") + machine;
  plate.certificate = dir + ".plate.csv";
  {
    FILE* f = std::fopen(plate.certificate.c_str(), "w");
    for (int ball = 0; ball < dg::sim::kBallPlateBalls; ++ball) {
      double x = 0, y = 0;
      dg::sim::ball_plate_centre(ball, &x, &y);
      std::fprintf(f, "%g,%g\n", x, y);
    }
    std::fclose(f);
  }
  if (dg::host::run_calibrate(plate) != 0) return 1;
  // The sphere again, with the axes in place: its tilt and lead no longer carry their stretch.
  if (dg::host::run_calibrate(sphere) != 0) return 1;
  const double calibrate_s = std::chrono::duration<double>(Clock::now() - start).count();
  const dg::host::TableCalibration c = dg::host::read_calibration_file(cal);
  double u_max = 0, map_max = 0;
  for (size_t k = 0; k < c.u_mm.size(); ++k) u_max = std::fmax(u_max, c.u_mm[k]), map_max = std::fmax(map_max, std::fabs(c.z_error_mm[k]));
  std::printf("flat 100 x 100 mm at 5 mm (441 readings, 1 um noise): travel error up to %.1f um found, map u <= %.2f um, "
              "noise %.2f um\n", map_max * 1e3, u_max * 1e3, c.noise_mm * 1e3);
  std::printf("ball plate, 9 balls at 1 mm (7,921 readings): scale x %+.1f ppm (u %.1f, true +200), scale y %+.1f ppm (u %.1f, "
              "true -150), squareness %+.1f urad (u %.1f, true +500)\n",
              c.scale_x_ppm, c.u_scale_x_ppm, c.scale_y_ppm, c.u_scale_y_ppm, c.squareness_urad, c.u_squareness_urad);
  // The simulator's bows (8 and -5 um at mid-travel) over the plate's 70 mm between its outer balls: S (35 / 50)^2.
  std::printf("  straightness (bow over the outer balls' span): x %+.2f um (u %.2f, true +3.92), y %+.2f um (u %.2f, true "
              "-2.45)\n", c.straightness.x_um, c.straightness.u_x_um, c.straightness.y_um, c.straightness.u_y_um);
  std::printf("step gauge, 6 steps 2 to 12 mm at 0.5 mm: gauge scale %+.0f ppm (u %.0f, true +400)\n", c.gauge_scale_ppm,
              c.u_gauge_scale_ppm);
  std::printf("reference sphere, 25.4 mm at 0.5 mm (%zu readings on its cap): gauge tilt x %+.0f urad (u %.0f, true +3000), "
              "y %+.0f urad (u %.0f, true -2000); the four artefacts (the sphere twice) %.2f s\n",
              c.sphere_points, c.gauge_tilt_x_urad, c.u_gauge_tilt_x_urad, c.gauge_tilt_y_urad, c.u_gauge_tilt_y_urad, calibrate_s);
  std::printf("  and the lead screws' periodic error (8 mm a turn): %.2f um in x (u %.2f), %.2f um in y (u %.2f), true 3\n",
              c.lead.amplitude_x_um(), c.lead.u_x_um, c.lead.amplitude_y_um(), c.lead.u_y_um);
  std::printf("%-9s %22s %22s\n", "part", "uncorrected max/RMS um", "corrected max/RMS um");
  // What one flat cannot tell: the plane taken out of the map, less the flat's own 5 mm.
  // The flat read its 5 mm with the gauge's scale, which corrected heights have taken out.
  auto plane = [&](double x, double y) {
    return (c.plane_mm[0] + c.plane_mm[1] * x + c.plane_mm[2] * y) / (1 + c.gauge_scale_ppm * 1e-6) - 5.0;
  };
  for (dg::sim::PartKind kind : {dg::sim::PartKind::kDome, dg::sim::PartKind::kSaddle, dg::sim::PartKind::kCanister,
                                 dg::sim::PartKind::kFlat}) {
    const std::string scan = dir + "." + dg::sim::part_name(kind) + ".scan";
    dg::host::ScanArgs s;
    s.device = std::string("sim:seed=22,part=") + dg::sim::part_name(kind) + "," + machine;
    s.calibration = cal;
    s.output = scan;
    s.force = true;
    s.quiet = true;
    if (dg::host::run_scan(s) != 0) return 1;
    const dg::host::PointCloud corrected = dg::host::read_points(scan);
    const dg::host::ScanData raw = dg::host::read_scan_file(scan);
    double worst[2] = {0, 0}, ss[2] = {0, 0};
    for (size_t k = 0; k < corrected.points.size(); ++k) {
      // Each point against the true part where the scan says it is: the raw one at its commanded
      // (x, y), the corrected one at the (x, y) the calibration moved it to.
      const dg::host::Point3& p = corrected.points[k];
      const double rx = raw.points[k].x_nm * 1e-6, ry = raw.points[k].y_nm * 1e-6;
      const double error[2] = {raw.points[k].z_nm * 1e-6 - dg::sim::shape_height_mm(kind, rx, ry) - plane(rx, ry),
                               p.z - dg::sim::shape_height_mm(kind, p.x, p.y) - plane(rx, ry)};
      for (int m = 0; m < 2; ++m) worst[m] = std::fmax(worst[m], std::fabs(error[m])), ss[m] += error[m] * error[m];
    }
    const double n = static_cast<double>(corrected.points.size());
    std::printf("%-9s %13.2f / %5.2f %13.2f / %5.2f\n", dg::sim::part_name(kind), worst[0] * 1e3, std::sqrt(ss[0] / n) * 1e3,
                worst[1] * 1e3, std::sqrt(ss[1] / n) * 1e3);
    std::remove(scan.c_str());
  }
  std::printf("(1 um of noise read to 1 um is 1.04 um a reading; the target is 2 um + the noise)\n");
  // The stand's drift: a warm-up of 25 um with a 3-minute time constant and 20 um an hour of creep,
  // over a scan of about 5 minutes, with the first point read again every N lines (0: never).
  std::printf("drift removal, the saddle at 1 um with a stand warming 25 um (3 min) and creeping 20 um/h:\n");
  std::printf("%-16s %22s %14s %16s\n", "reference every", "error max/RMS um", "device time s", "added u max um");
  for (uint32_t every : {0u, 1u, 2u, 5u}) {
    const std::string scan = dir + ".drift.scan";
    dg::host::ScanArgs s;
    s.device = "sim:seed=24,part=saddle,noise_um=1,warmup_um=25,warmup_min=3,drift_um_per_h=20";
    s.reference_every = every;
    s.repeatability = 20;
    s.output = scan;
    s.force = true;
    s.quiet = true;
    if (dg::host::run_scan(s) != 0) return 1;
    const dg::host::PointCloud corrected = dg::host::read_points(scan);
    const dg::host::PointCloud as_measured = dg::host::read_points(scan, true);
    double worst = 0, ss = 0, added = 0;
    for (size_t k = 0; k < corrected.points.size(); ++k) {
      const dg::host::Point3& p = corrected.points[k];
      const double error = p.z - dg::sim::shape_height_mm(dg::sim::PartKind::kSaddle, p.x, p.y);
      worst = std::fmax(worst, std::fabs(error)), ss += error * error;
      if (corrected.sigma && as_measured.sigma) {
        const double a = (*corrected.sigma)[k], b = (*as_measured.sigma)[k];
        added = std::fmax(added, std::sqrt(std::fmax(0.0, a * a - b * b)));
      }
    }
    const dg::host::ScanData raw = dg::host::read_scan_file(scan);
    const double device_s = raw.done ? static_cast<double>(raw.done->duration_us) * 1e-6 : 0;
    std::printf("%-16s %13.2f / %5.2f %14.1f %16.2f\n", every == 0 ? "never" : (std::to_string(every) + " lines").c_str(),
                worst * 1e3, std::sqrt(ss / static_cast<double>(corrected.points.size())) * 1e3, device_s, added * 1e3);
    std::remove(scan.c_str());
  }
  std::remove(cal.c_str());
  std::remove((cal + ".flat.scan").c_str());
  std::remove((cal + ".ballplate.scan").c_str());
  std::remove((cal + ".sphere.scan").c_str());
  std::remove((cal + ".stepgauge.scan").c_str());
  std::remove(steps.certificate.c_str());
  std::remove((dir + ".plate.csv").c_str());
  return 0;
}
