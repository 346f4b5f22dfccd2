// The simulated table's geometric errors and the gauge stand's drift, in closed form.
#include "hw/sim/machine_errors.h"

#include <cmath>

#include "hw/sim/random.h"

namespace dg::sim {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTravelMm = 100.0;  // the map's modes span this much travel on each axis
constexpr int kModes = 4;

// The map before scaling: a bowl and kModes cosine products of one or two half-waves over the
// travel, with amplitudes and phases from the seed. Smooth, as ground ways and a cast table are.
double raw_map(uint64_t seed, double x_mm, double y_mm) {
  Random random(seed * 2654435761u + 97);
  const double u = x_mm / kTravelMm, v = y_mm / kTravelMm;
  double z = 0.6 * ((u - 0.5) * (u - 0.5) + (v - 0.5) * (v - 0.5));
  for (int m = 0; m < kModes; ++m) {
    const double kx = 1 + (random.next_u32() % 2), ky = 1 + (random.next_u32() % 2);
    const double px = 2 * kPi * random.uniform(), py = 2 * kPi * random.uniform();
    const double amplitude = 0.15 + 0.2 * random.uniform();
    z += amplitude * std::cos(kPi * kx * u + px) * std::cos(kPi * ky * v + py);
  }
  return z;
}

// The largest |raw map| over the travel on a 2 mm grid, so that flatness_um is the peak.
double raw_peak(uint64_t seed) {
  double peak = 0;
  for (int i = 0; i <= 50; ++i)
    for (int j = 0; j <= 50; ++j) peak = std::fmax(peak, std::fabs(raw_map(seed, 2.0 * i, 2.0 * j)));
  return peak > 0 ? peak : 1;
}

}  // namespace

// One screw's periodic error at commanded position t (mm), zero at the origin.
double lead_error_mm(const MachineErrors& e, double t_mm, double phase) {
  if (e.lead_error_um == 0) return 0;
  return e.lead_error_um * 1e-3 * (std::sin(2 * kPi * t_mm / e.lead_mm + phase) - std::sin(phase));
}

void actual_table_xy(const MachineErrors& e, double x_mm, double y_mm, double* actual_x_mm, double* actual_y_mm) {
  const double u = x_mm / kTravelMm, v = y_mm / kTravelMm;
  Random random(e.map_seed * 40503u + 11);
  const double phase_x = 2 * kPi * random.uniform(), phase_y = 2 * kPi * random.uniform();
  *actual_x_mm = x_mm * (1 + e.scale_x_ppm * 1e-6) + y_mm * std::sin(e.squareness_urad * 1e-6) +
                 e.straightness_x_um * 1e-3 * 4 * v * (1 - v) + lead_error_mm(e, x_mm, phase_x);
  *actual_y_mm = y_mm * (1 + e.scale_y_ppm * 1e-6) * std::cos(e.squareness_urad * 1e-6) +
                 e.straightness_y_um * 1e-3 * 4 * u * (1 - u) + lead_error_mm(e, y_mm, phase_y);
}

double flatness_map_peak(uint64_t map_seed) { return raw_peak(map_seed); }

double travel_z_error_mm(const MachineErrors& e, double map_peak, double x_mm, double y_mm) {
  if (e.flatness_um == 0) return 0;
  return e.flatness_um * 1e-3 * raw_map(e.map_seed, x_mm, y_mm) / map_peak;
}

double drift_mm(const MachineErrors& e, uint64_t t_ns) {
  const double t_s = static_cast<double>(t_ns) * 1e-9;
  const double warmup = e.warmup_um == 0 ? 0 : e.warmup_um * (1 - std::exp(-t_s / (60 * e.warmup_min)));
  return 1e-3 * (e.drift_um_per_h * t_s / 3600.0 + warmup);
}

}  // namespace dg::sim
