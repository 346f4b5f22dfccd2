// Virtual parts for the simulated table: analytic height fields z(x, y) in millimetres.
#pragma once

namespace dg::sim {

enum class PartKind { kDome, kSaddle, kCanister, kFlat, kBallPlate, kSphere, kStepGauge };

struct Part {
  PartKind kind = PartKind::kDome;
  double offset_mm = 0.0;  // raises or lowers the whole part (gauge zero elsewhere)
  // Where the part lies on the table: its own frame's origin, and its x axis this far
  // anticlockwise from the table's (a reference artefact laid in several positions).
  double x0_mm = 0.0, y0_mm = 0.0, angle_deg = 0.0;
  // Height of the part's top surface above the table at table position (x, y), mm.
  double height_mm(double x_mm, double y_mm) const;
};

// The shape alone, without offset.
double shape_height_mm(PartKind kind, double x_mm, double y_mm);

// Parses "dome", "saddle", "canister", "flat"; false if unknown.
bool parse_part(const char* name, PartKind* kind);
const char* part_name(PartKind kind);

// The ball plate, a reference artefact for the axes' scale and squareness: a 2 mm plate with
// kBallPlateBalls balls of radius kBallRadiusMm standing 4 mm proud of it, their centres on a 3 x 3
// grid 35 mm apart from (15, 15) mm (its certificate: docs/ball-plate-sim.csv).
constexpr int kBallPlateBalls = 9;
constexpr double kBallRadiusMm = 6.0;
void ball_plate_centre(int ball, double* x_mm, double* y_mm);

// The reference sphere, for the gauge's tilt: a ball kSphereRadiusMm in radius (25.4 mm across, the
// usual size of a reference sphere) on a stem, its centre kSphereCentreZMm above the table at
// (kSphereXMm, kSphereYMm); around the stem a 2 mm base. Its certificate is the diameter alone.
constexpr double kSphereRadiusMm = 12.7;
constexpr double kSphereXMm = 20.0, kSphereYMm = 15.0, kSphereCentreZMm = 8.0;

// The step gauge, for the gauge's scale: kSteps blocks kStepWidthMm wide along x from
// kStepX0Mm, each kStepDepthMm deep in y from kStepY0Mm, standing on a 1 mm plate, the first 2 mm
// high and each next 2 mm higher (its certificate: docs/step-gauge-sim.csv, the tops above the
// plate's top plus its 1 mm). Beyond y0 + depth the plate shows beside every block.
constexpr int kSteps = 6;
constexpr double kStepX0Mm = 5.0, kStepWidthMm = 6.0, kStepY0Mm = 5.0, kStepDepthMm = 10.0;
double step_height_mm(int step);

// The saddle's coefficients (z = a + b x + c y + d x y), exposed for tests.
struct SaddleCoefficients {
  double a = 5.0, b = 0.05, c = -0.04, d = 0.004;
};

}  // namespace dg::sim
