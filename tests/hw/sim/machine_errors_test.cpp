// The simulated machine's errors: off by default, each as large as asked, and seen by the gauge.
#include <CppUTest/TestHarness.h>

#include <cmath>
#include <string>

#include "hw/sim/machine_errors.h"
#include "hw/sim/parts.h"
#include "hw/sim/sim_board.h"
#include "hw/sim/sim_options.h"

using namespace dg::sim;

TEST_GROUP(MachineErrors){};

TEST(MachineErrors, AnIdealMachineMovesWhereItIsToldAndAddsNoHeight) {
  const MachineErrors ideal;
  CHECK_FALSE(ideal.any());
  double x = 0, y = 0;
  actual_table_xy(ideal, 37.5, 81.25, &x, &y);
  DOUBLES_EQUAL(37.5, x, 0);
  DOUBLES_EQUAL(81.25, y, 0);
  DOUBLES_EQUAL(0, travel_z_error_mm(ideal, 1, 50, 50), 0);
}

TEST(MachineErrors, TheTravelsFlatnessPeaksAtTheAmountAskedAndIsTheSameForEveryScanSeed) {
  MachineErrors e;
  e.flatness_um = 30;
  const double peak = flatness_map_peak(e.map_seed);
  double largest = 0;
  for (int i = 0; i <= 100; ++i)
    for (int j = 0; j <= 100; ++j) largest = std::fmax(largest, std::fabs(travel_z_error_mm(e, peak, i, j)));
  DOUBLES_EQUAL(0.030, largest, 0.0005);
  // Smooth: a millimetre apart, heights differ by a small part of the peak.
  DOUBLES_EQUAL(travel_z_error_mm(e, peak, 40, 60), travel_z_error_mm(e, peak, 41, 60), 0.002);
  MachineErrors other = e;
  other.map_seed = 2;
  CHECK(std::fabs(travel_z_error_mm(e, peak, 20, 70) - travel_z_error_mm(other, flatness_map_peak(2), 20, 70)) > 1e-4);
}

TEST(MachineErrors, SquarenessAndScaleMoveTheTableAwayFromTheCommandedPoint) {
  MachineErrors e;
  e.squareness_urad = 500;
  e.scale_x_ppm = 200;
  e.scale_y_ppm = -150;
  double x = 0, y = 0;
  actual_table_xy(e, 100, 100, &x, &y);
  DOUBLES_EQUAL(100 + 0.020 + 0.050, x, 1e-6);  // 200 ppm of 100 mm, and 0.5 mrad of the 100 mm in y
  DOUBLES_EQUAL(100 * (1 - 150e-6) * std::cos(500e-6), y, 1e-9);  // and the leaning axis is a cosine shorter
}

TEST(MachineErrors, BentWaysBowEachAxisPathAtMidTravelAndNotAtItsEnds) {
  SimOptions o;
  STRCMP_EQUAL("", apply_sim_option("straightness_x_um=8", &o).c_str());
  STRCMP_EQUAL("", apply_sim_option("straightness_y_um=-5", &o).c_str());
  CHECK(o.config.machine.any());
  const MachineErrors& e = o.config.machine;
  double x = 0, y = 0;
  actual_table_xy(e, 20, 50, &x, &y);  // y at mid-travel: x wanders by the whole bow
  DOUBLES_EQUAL(20.008, x, 1e-12);
  DOUBLES_EQUAL(50 - 0.005 * 4 * 0.2 * 0.8, y, 1e-12);
  actual_table_xy(e, 100, 0, &x, &y);  // both at an end of their travel: no bow
  DOUBLES_EQUAL(100, x, 1e-12);
  DOUBLES_EQUAL(0, y, 1e-12);
  CHECK(!apply_sim_option("straightness_x_um=2000", &o).empty());
}

TEST(MachineErrors, EachScrewRepeatsItsErrorEveryTurnUpToItsAmplitudeAndNoneAtTheOrigin) {
  SimOptions o;
  STRCMP_EQUAL("", apply_sim_option("lead_error_um=3", &o).c_str());
  STRCMP_EQUAL("", apply_sim_option("lead_mm=5", &o).c_str());
  CHECK(o.config.machine.any());
  const MachineErrors& e = o.config.machine;
  double x = 0, y = 0, largest = 0;
  actual_table_xy(e, 0, 0, &x, &y);
  DOUBLES_EQUAL(0, x, 1e-15);
  DOUBLES_EQUAL(0, y, 1e-15);
  for (double t = 0; t < 5; t += 0.05) {
    double x2 = 0, y2 = 0;
    actual_table_xy(e, t, t, &x, &y);
    actual_table_xy(e, t + 15, t + 35, &x2, &y2);  // three and seven turns on
    DOUBLES_EQUAL(x - t, x2 - t - 15, 1e-12);
    DOUBLES_EQUAL(y - t, y2 - t - 35, 1e-12);
    largest = std::fmax(largest, std::fabs(x - t));
  }
  CHECK(largest > 0.001 && largest <= 0.006);  // a sine's swing less its value at the origin
  CHECK(!apply_sim_option("lead_mm=0", &o).empty());
}

TEST(MachineErrors, TheGaugeReadsThePartWhereTheTableReallyIsPlusTheTravelsErrorAndDrift) {
  SimOptions o;
  for (const char* pair : {"part=saddle", "squareness_urad=1000", "scale_x_ppm=500", "flatness_um=20", "drift_um_per_h=360"}) {
    STRCMP_EQUAL("", apply_sim_option(pair, &o).c_str());
  }
  o.config.start_x_steps = 30 * 400;  // 30 mm at 2.5 um a step
  o.config.start_y_steps = 20 * 400;
  SimBoard board(o.config, nullptr);
  const MachineErrors& e = o.config.machine;
  double x = 0, y = 0;
  actual_table_xy(e, 30, 20, &x, &y);
  const double expected = o.config.part.height_mm(x, y) + travel_z_error_mm(e, flatness_map_peak(e.map_seed), 30, 20);
  DOUBLES_EQUAL(expected, board.height_under_probe_mm(), 1e-12);
  DOUBLES_EQUAL(0.180, drift_mm(e, 1800000000000ull), 1e-12);  // 360 um an hour, for half an hour
  // The saddle's slope turns the table's 35 um offset in x into a height error of its own.
  CHECK(std::fabs(o.config.part.height_mm(x, y) - o.config.part.height_mm(30, 20)) > 0.004);
}

// A leaning gauge reads along its own axis: where the plunger meets the part, r along that axis
// from the gauge's zero. On a plane z = a + b x the reading has a closed form: r cos = a + b (x +
// r sin_x), r = (a + b x) / (cos - b sin_x); on the sphere it is the upper root of the line's
// intersection with the ball.
TEST(MachineErrors, ALeaningGaugeReadsAlongItsAxisWhereThePlungerMeetsThePart) {
  const double tx = 4e-3, ty = -2.5e-3;
  const double sx = std::sin(tx), sy = std::sin(ty), cos_tilt = std::sqrt(1 - sx * sx - sy * sy);
  for (const char* part : {"part=flat", "part=sphere"}) {
    SimOptions o;
    for (const char* pair : {part, "gauge_tilt_x_urad=4000", "gauge_tilt_y_urad=-2500"}) STRCMP_EQUAL("", apply_sim_option(pair, &o).c_str());
    CHECK(o.config.machine.any());
    o.config.start_x_steps = 24 * 400;  // (24, 17) mm, on the sphere's flank
    o.config.start_y_steps = 17 * 400;
    SimBoard board(o.config, nullptr);
    double expected = 0;
    if (std::string(part) == "part=flat") {
      expected = 5.0 / cos_tilt;  // the flat's 5 mm, read along the axis
    } else {
      // |(24 + r sx - 20, 17 + r sy - 15, r cos - zc)|^2 = R^2, the larger root.
      const double px = 24 - dg::sim::kSphereXMm, py = 17 - dg::sim::kSphereYMm, pz = -dg::sim::kSphereCentreZMm;
      const double b = px * sx + py * sy + pz * cos_tilt;
      const double c = px * px + py * py + pz * pz - dg::sim::kSphereRadiusMm * dg::sim::kSphereRadiusMm;
      expected = -b + std::sqrt(b * b - c);
      // On the sphere's flank the lean moves the reading by micrometres from a vertical gauge's.
      CHECK(std::fabs(expected - o.config.part.height_mm(24, 17)) > 0.005);
    }
    DOUBLES_EQUAL(expected, board.height_under_probe_mm(), 1e-9);
  }
  SimOptions o;
  STRCMP_CONTAINS("gauge_tilt_x_urad must be", apply_sim_option("gauge_tilt_x_urad=60000", &o).c_str());
}

// The step gauge's tops stand at their certified heights, and a gauge reading 400 ppm long reads
// each 400 ppm high.
TEST(MachineErrors, AGaugeWithAScaleErrorReadsTheStepGaugesTopsThatMuchLong) {
  for (int step = 0; step < dg::sim::kSteps; ++step) {
    SimOptions o;
    for (const char* pair : {"part=stepgauge", "gauge_scale_ppm=400"}) STRCMP_EQUAL("", apply_sim_option(pair, &o).c_str());
    const double x_mm = dg::sim::kStepX0Mm + (step + 0.5) * dg::sim::kStepWidthMm, y_mm = 10;
    DOUBLES_EQUAL(2.0 + 2.0 * step, o.config.part.height_mm(x_mm, y_mm), 0);
    o.config.start_x_steps = static_cast<int64_t>(x_mm * 400);
    o.config.start_y_steps = static_cast<int64_t>(y_mm * 400);
    SimBoard board(o.config, nullptr);
    DOUBLES_EQUAL((2.0 + 2.0 * step) * 1.0004, board.height_under_probe_mm(), 1e-12);
  }
  SimOptions o;
  STRCMP_EQUAL("", apply_sim_option("part=stepgauge", &o).c_str());
  DOUBLES_EQUAL(1.0, o.config.part.height_mm(8, 20), 0);  // its plate, beside the first step
  STRCMP_CONTAINS("gauge_scale_ppm must be", apply_sim_option("gauge_scale_ppm=1e6", &o).c_str());
}

// The stand's warm-up settles as a first-order lag: 63 % of it after one time constant, and on
// top of the steady creep.
TEST(MachineErrors, TheStandsWarmUpSettlesWithItsTimeConstantOnTopOfItsCreep) {
  SimOptions o;
  for (const char* pair : {"warmup_um=30", "warmup_min=5", "drift_um_per_h=60"}) STRCMP_EQUAL("", apply_sim_option(pair, &o).c_str());
  const MachineErrors& e = o.config.machine;
  CHECK(e.any());
  const uint64_t five_minutes_ns = 300000000000ull;
  DOUBLES_EQUAL(0.030 * (1 - std::exp(-1.0)) + 0.005, drift_mm(e, five_minutes_ns), 1e-12);
  DOUBLES_EQUAL(0.030 + 0.060, drift_mm(e, 3600 * 1000000000ull), 1e-6);  // settled after an hour
  STRCMP_CONTAINS("warmup_min", apply_sim_option("warmup_min=0", &o).c_str());
}

TEST(MachineErrors, BadValuesAreRefusedWithTheirName) {
  SimOptions o;
  STRCMP_CONTAINS("flatness_um", apply_sim_option("flatness_um=abc", &o).c_str());
  STRCMP_CONTAINS("squareness_urad", apply_sim_option("squareness_urad=1e9", &o).c_str());
  STRCMP_CONTAINS("machine is typical or ideal", apply_sim_option("machine=wobbly", &o).c_str());
  STRCMP_EQUAL("", apply_sim_option("machine=typical", &o).c_str());
  CHECK(o.config.machine.any());
  DOUBLES_EQUAL(30, o.config.machine.flatness_um, 0);
}
