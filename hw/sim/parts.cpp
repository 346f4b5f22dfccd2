// The parts: a spherical dome, a bilinear saddle, and a concave canister face (Hamdan 2010
// section 4 digitizes a perfume canister with a concave surface at 1 mm increments).
#include "hw/sim/parts.h"

#include <cmath>
#include <cstring>

namespace dg::sim {

double Part::height_mm(double x_mm, double y_mm) const {
  if (x0_mm == 0.0 && y0_mm == 0.0 && angle_deg == 0.0) return offset_mm + shape_height_mm(kind, x_mm, y_mm);
  const double a = angle_deg * 3.14159265358979323846 / 180.0, c = std::cos(a), s = std::sin(a);
  const double dx = x_mm - x0_mm, dy = y_mm - y0_mm;
  return offset_mm + shape_height_mm(kind, c * dx + s * dy, -s * dx + c * dy);
}

double shape_height_mm(PartKind kind, double x_mm, double y_mm) {
  switch (kind) {
    case PartKind::kDome: {
      // Spherical cap, radius 30 mm, 8 mm high, centred at (20, 15), on a 2 mm base plate.
      const double r = 30.0, h = 8.0, cx = 20.0, cy = 15.0, base = 2.0;
      const double d2 = (x_mm - cx) * (x_mm - cx) + (y_mm - cy) * (y_mm - cy);
      const double cap = r * r > d2 ? std::sqrt(r * r - d2) - (r - h) : 0.0;
      return base + (cap > 0.0 ? cap : 0.0);
    }
    case PartKind::kSaddle: {
      const SaddleCoefficients k;
      return k.a + k.b * x_mm + k.c * y_mm + k.d * x_mm * y_mm;
    }
    case PartKind::kCanister: {
      // A 12 mm high face with a smooth elliptical dish 4 mm deep in its middle and
      // gently rounded long edges, like the side of a perfume bottle.
      const double cx = 20.0, cy = 15.0, ax = 14.0, ay = 10.0;
      const double u = (x_mm - cx) / ax, v = (y_mm - cy) / ay;
      const double dish = 4.0 * std::exp(-(u * u + v * v));
      const double edge = 0.02 * (y_mm - cy) * (y_mm - cy);
      return 12.0 - dish - edge;
    }
    case PartKind::kFlat:
      return 5.0;
    case PartKind::kBallPlate: {
      // Centres 2 mm below the plate's top, so each ball stands 4 mm proud with a 5.66 mm footprint.
      const double plate = 2.0, centre_z = plate + 4.0 - kBallRadiusMm;
      double z = plate;
      for (int ball = 0; ball < kBallPlateBalls; ++ball) {
        double cx = 0, cy = 0;
        ball_plate_centre(ball, &cx, &cy);
        const double d2 = (x_mm - cx) * (x_mm - cx) + (y_mm - cy) * (y_mm - cy);
        if (d2 < kBallRadiusMm * kBallRadiusMm) z = std::fmax(z, centre_z + std::sqrt(kBallRadiusMm * kBallRadiusMm - d2));
      }
      return z;
    }
    case PartKind::kStepGauge: {
      const double k = std::floor((x_mm - kStepX0Mm) / kStepWidthMm);
      if (k < 0 || k >= kSteps || y_mm < kStepY0Mm || y_mm >= kStepY0Mm + kStepDepthMm) return 1.0;
      return step_height_mm(static_cast<int>(k));
    }
    case PartKind::kSphere: {
      const double d2 = (x_mm - kSphereXMm) * (x_mm - kSphereXMm) + (y_mm - kSphereYMm) * (y_mm - kSphereYMm);
      const double r2 = kSphereRadiusMm * kSphereRadiusMm;
      return d2 < r2 ? kSphereCentreZMm + std::sqrt(r2 - d2) : 2.0;
    }
  }
  return 0.0;
}

double step_height_mm(int step) { return 2.0 + 2.0 * step; }

void ball_plate_centre(int ball, double* x_mm, double* y_mm) {
  *x_mm = 15.0 + 35.0 * (ball % 3);
  *y_mm = 15.0 + 35.0 * (ball / 3);
}

bool parse_part(const char* name, PartKind* kind) {
  static const struct {
    const char* name;
    PartKind kind;
  } kParts[] = {{"dome", PartKind::kDome},
                {"saddle", PartKind::kSaddle},
                {"canister", PartKind::kCanister},
                {"flat", PartKind::kFlat},
                {"ballplate", PartKind::kBallPlate},
                {"sphere", PartKind::kSphere},
                {"stepgauge", PartKind::kStepGauge}};
  for (const auto& p : kParts) {
    if (std::strcmp(p.name, name) == 0) {
      *kind = p.kind;
      return true;
    }
  }
  return false;
}

const char* part_name(PartKind kind) {
  switch (kind) {
    case PartKind::kDome: return "dome";
    case PartKind::kSaddle: return "saddle";
    case PartKind::kCanister: return "canister";
    case PartKind::kFlat: return "flat";
    case PartKind::kBallPlate: return "ballplate";
    case PartKind::kSphere: return "sphere";
    case PartKind::kStepGauge: return "stepgauge";
  }
  return "?";
}

}  // namespace dg::sim
