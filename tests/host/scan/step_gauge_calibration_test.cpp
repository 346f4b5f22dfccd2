// The gauge's scale from a step gauge, against steps read in closed form with a known scale and
// noise, the uncertainty against the spread of many replicas, and what it refuses.
#include <CppUTest/TestHarness.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "host/scan/step_gauge_calibration.h"

using namespace dg::host;

namespace {

const std::vector<double> kCertified = {2, 4, 6, 8, 10, 12};

// Six blocks 6 mm wide along x from 5 mm, 10 mm deep in y from 5 mm, on a 1 mm plate, read at
// 0.5 mm over x 5.5..40.5 and 1 mm over y 6..`y1_mm` (beyond 15 mm: the plate beside them), by a
// gauge reading (1 + scale) times the height, 0.3 mm added (its zero elsewhere), on a travel
// tilted `tilt_x` along x, with Gaussian noise, rounded to 1 um.
PointCloud steps(double scale, double noise_mm, unsigned seed, double tilt_x = 0, double y1_mm = 24, bool along_y = false) {
  std::mt19937 random(seed);
  std::normal_distribution<double> noise(0.0, noise_mm);
  PointCloud cloud;
  for (double y = 6; y <= y1_mm; y += 1) {
    for (double x = 5.5; x <= 40.5; x += 0.5) {
      const int k = static_cast<int>(std::floor((x - 5) / 6));
      const double height = k >= 0 && k < 6 && y < 15 ? kCertified[static_cast<size_t>(k)] : 1.0;
      const double z = (height + 0.3 + tilt_x * x) * (1 + scale) + (noise_mm > 0 ? noise(random) : 0.0);
      // Turned a quarter: the steps run along y, the plate beside them at smaller x.
      if (along_y) cloud.points.push_back({60 - y, x, std::round(z * 1e3) * 1e-3});
      else cloud.points.push_back({x, y, std::round(z * 1e3) * 1e-3});
    }
  }
  return cloud;
}

std::string refusal(const PointCloud& cloud, const std::vector<double>& certified) {
  try {
    calibrate_gauge_scale(cloud, certified, "steps.scan");
  } catch (const CalibrationError& error) {
    return error.what();
  }
  return "";
}

}  // namespace

TEST_GROUP(StepGaugeCalibration){};

TEST(StepGaugeCalibration, AScaleOfAFewHundredPpmIsFoundFromTheStepsHeights) {
  for (const double scale : {400e-6, -1500e-6, 0.0}) {
    const GaugeScale g = calibrate_gauge_scale(steps(scale, 0.001, 3), kCertified, "steps.scan");
    DOUBLES_EQUAL(scale * 1e6, g.scale_ppm, 4 * g.u_scale_ppm);
    CHECK(g.u_scale_ppm > 0 && g.u_scale_ppm < 30);
    LONGS_EQUAL(6, g.steps.size());
    DOUBLES_EQUAL(kCertified[2] - 1.0, g.steps[2].height_mm, 0.02);  // above the plate
    DOUBLES_EQUAL(8.0, g.steps[0].x_mm, 0.3);  // in order along x (the scan ends 0.5 mm inside)
    DOUBLES_EQUAL(38.0, g.steps[5].x_mm, 0.3);
  }
}

// The travel tilted 100 urad along x raises each step 6 mm further on by 0.6 um, which tops alone
// would read as 300 ppm of scale; against the plate beside each it cancels.
TEST(StepGaugeCalibration, ATiltOfTheTravelAlongTheStepsCancelsAgainstThePlateBesideThem) {
  const GaugeScale g = calibrate_gauge_scale(steps(400e-6, 0.0005, 9, 100e-6), kCertified, "steps.scan");
  DOUBLES_EQUAL(400, g.scale_ppm, 4 * g.u_scale_ppm);
  CHECK(g.u_scale_ppm < 20);
}

// The steps run along y on a gauge turned a quarter, and the certificate lists them in another
// order: each is matched by height, and the plate beside each is found across the row.
TEST(StepGaugeCalibration, TurnedAQuarterWithItsCertificateInAnotherOrderTheStepsAreStillMatched) {
  const std::vector<double> shuffled = {8, 2, 12, 4, 10, 6};
  const GaugeScale g = calibrate_gauge_scale(steps(400e-6, 0.0005, 4, 0, 24, true), shuffled, "steps.scan");
  DOUBLES_EQUAL(400, g.scale_ppm, 4 * g.u_scale_ppm);
  for (size_t k = 0; k < shuffled.size(); ++k) DOUBLES_EQUAL((shuffled[k] - 1.0) * 1.0004, g.steps[k].height_mm, 0.002);
  DOUBLES_EQUAL(26.0, g.steps[0].y_mm, 0.3);  // the 8 mm step: fourth along the row, now along y
}

TEST(StepGaugeCalibration, TheStatedUncertaintyMatchesTheSpreadOfRepeatedCalibrations) {
  constexpr int kReplicas = 200;
  double sum = 0, sum_sq = 0, stated = 0;
  for (int k = 0; k < kReplicas; ++k) {
    const GaugeScale g = calibrate_gauge_scale(steps(400e-6, 0.002, 50 + k), kCertified, "steps.scan");
    sum += g.scale_ppm, sum_sq += g.scale_ppm * g.scale_ppm, stated += g.u_scale_ppm / kReplicas;
  }
  const double mean = sum / kReplicas, spread = std::sqrt((sum_sq - kReplicas * mean * mean) / (kReplicas - 1));
  std::printf("\n  scale: mean %.1f ppm (true 400), spread %.1f, stated u %.1f", mean, spread, stated);
  // Birge's ratio inflates u when a replica's 6 heights scatter more than stated, never deflates
  // it: the mean u stays at or a little above the spread.
  CHECK(spread / stated > 0.85 && spread / stated < 1.15);
  DOUBLES_EQUAL(400, mean, 4 * stated / std::sqrt(kReplicas));
}

TEST(StepGaugeCalibration, StepsThatDoNotMatchTheCertificateAreRefusedWithTheReason) {
  STRCMP_CONTAINS("fall into 7 levels; the plate and the certificate's 5 steps make 6",
                  refusal(steps(0, 0.001, 1), {2, 4, 6, 8, 10}).c_str());
  // The tops alone, no plate beside them: the lowest top is taken for the plate.
  STRCMP_CONTAINS("fall into 6 levels; the plate and the certificate's 6 steps make 7",
                  refusal(steps(0, 0.001, 1, 0, 14), kCertified).c_str());
  STRCMP_CONTAINS("ppm off their certified heights", refusal(steps(0, 0.001, 1), {2.1, 4.2, 6.3, 8.4, 10.5, 12.6}).c_str());
  STRCMP_CONTAINS("closer than 0.5 mm in height", refusal(steps(0, 0.001, 1), {2, 4, 6, 8, 10, 10.2}).c_str());
  STRCMP_CONTAINS("at least 2 certified steps", refusal(steps(0, 0.001, 1), {2}).c_str());
  STRCMP_CONTAINS("fall into 0 levels", refusal(PointCloud{}, kCertified).c_str());
}

TEST(StepGaugeCalibration, TheCertificateIsReadWithAHeaderAndRefusedWithTheLineThatIsWrong) {
  const std::string path = std::string(P_tmpdir) + "/dg_steps_" + std::to_string(getpid()) + ".csv";
  auto read = [&](const char* text) -> std::string {
    FILE* f = std::fopen(path.c_str(), "w");
    std::fputs(text, f);
    std::fclose(f);
    try {
      const std::vector<double> h = read_step_certificate(path);
      return "read " + std::to_string(h.size());
    } catch (const CalibrationError& error) {
      return error.what();
    }
  };
  STRCMP_EQUAL("read 3", read("height_mm\n2\n4.0005\r\n6\n").c_str());
  STRCMP_CONTAINS(":3: expected a height in mm, got '4,5'", read("height_mm\n2\n4,5\n").c_str());
  STRCMP_CONTAINS("needs at least 2 steps", read("2\n").c_str());
  STRCMP_CONTAINS("height 2 is not within 1000 mm", read("2\n1e9\n").c_str());
  std::remove(path.c_str());
}
