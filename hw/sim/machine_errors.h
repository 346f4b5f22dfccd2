// The simulated machine's own errors: what a hobby XY table and its gauge stand do to every reading.
#pragma once
#include <cmath>
#include <cstdint>

namespace dg::sim {

// Each is off (zero) by default. Deterministic from the seed, so a calibration measured on one scan
// applies to a scan taken later with another seed for the gauge noise.
struct MachineErrors {
  double squareness_urad = 0;  // the y axis leans towards +x by this angle: x moves y * angle
  double scale_x_ppm = 0;      // the x screw's lead error: the table travels (1 + ppm 1e-6) of the command
  double scale_y_ppm = 0;
  // The ways are not straight: a bent rail bows the carriage's path. While y travels, x wanders by
  // straightness_x_um 4 v (1 - v), v = y / 100 mm (a bow, this high at mid-travel, nothing at its
  // ends); while x travels, y wanders by straightness_y_um 4 u (1 - u), u = x / 100 mm.
  double straightness_x_um = 0, straightness_y_um = 0;
  // The lead screws' periodic error: a bent screw or an off-centre nut moves the table ahead and
  // behind its command once a turn, lead_error_um at its largest, with a phase per axis from the
  // map seed, counted from the commanded origin (where homing leaves the screw).
  double lead_error_um = 0;
  double lead_mm = 8;  // the screws' lead: one turn moves the table this far (8 mm: a common T8 screw)
  // The table's travel is not flat: a smooth height error of the carriage over its XY travel
  // (low-order modes over 100 x 100 mm with a bowl), this many micrometres at its largest.
  double flatness_um = 0;
  double drift_um_per_h = 0;   // the gauge's stand warms: Z grows this much per hour of virtual time
  // And settles: a first-order warm-up that adds warmup_um * (1 - exp(-t / warmup_min)), the shape
  // a stand's temperature takes after the room or the motors change it, which no straight line follows.
  double warmup_um = 0;
  double warmup_min = 20;
  // The gauge's plunger is not vertical: its axis leans towards +x by gauge_tilt_x_urad and towards
  // +y by gauge_tilt_y_urad. A reading r (the plunger's travel from the gauge's zero, at the
  // table's height) touches the part at (x + r sin(tilt_x), y + r sin(tilt_y)), r cos(tilt) high.
  double gauge_tilt_x_urad = 0, gauge_tilt_y_urad = 0;
  // The gauge's scale: it reads (1 + gauge_scale_ppm 1e-6) times its plunger's travel from its zero.
  double gauge_scale_ppm = 0;
  uint64_t map_seed = 1;       // picks the flatness map's modes (the machine's, not the scan's)

  bool any() const {
    return squareness_urad != 0 || scale_x_ppm != 0 || scale_y_ppm != 0 || straightness_x_um != 0 ||
           straightness_y_um != 0 || lead_error_um != 0 || flatness_um != 0 || drift_um_per_h != 0 ||
           warmup_um != 0 || gauge_tilt_x_urad != 0 || gauge_tilt_y_urad != 0 ||
           gauge_scale_ppm != 0;
  }
};

// Where the table really is for a commanded position (mm).
void actual_table_xy(const MachineErrors& e, double x_mm, double y_mm, double* actual_x_mm, double* actual_y_mm);
// The flatness map's largest |value| before scaling, for travel_z_error_mm (a few ms: once per machine).
double flatness_map_peak(uint64_t map_seed);
// The travel's height error at a commanded position (mm), without drift.
double travel_z_error_mm(const MachineErrors& e, double map_peak, double x_mm, double y_mm);
// The reading of the leaning gauge over a surface: `height_mm(dx, dy)` is the height the tip meets
// when it stands (dx, dy) mm from where a vertical gauge would, travel error and drift included.
// The reading r solves r cos(tilt) = height(r sin(tilt_x), r sin(tilt_y)), by fixed-point
// iteration from the vertical reading (it contracts by slope x tilt: a few steps on any part whose
// slope is not near vertical; at a cliff it stops after kTiltIterations).
template <typename Height>
double tilted_reading_mm(const MachineErrors& e, Height height_mm) {
  constexpr int kTiltIterations = 40;
  const double sx = std::sin(e.gauge_tilt_x_urad * 1e-6), sy = std::sin(e.gauge_tilt_y_urad * 1e-6);
  const double cos_tilt = std::sqrt(1 - sx * sx - sy * sy);
  double r = height_mm(0.0, 0.0) / cos_tilt;
  for (int k = 0; k < kTiltIterations; ++k) {
    const double next = height_mm(r * sx, r * sy) / cos_tilt;
    if (std::fabs(next - r) < 1e-10) return next;
    r = next;
  }
  return r;
}

// The drift after `t_ns` of virtual time (mm).
double drift_mm(const MachineErrors& e, uint64_t t_ns);

}  // namespace dg::sim
