// Slopes from each point's neighbours on its line and the lines beside it, times the table's
// position uncertainty there.
#include "host/scan/position_uncertainty.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "host/scan/sorted_lines.h"

namespace dg::host {

double TablePosition::u_x_mm(double x_mm, double y_mm, double z_mm) const {
  const double step_sq = step_mm * step_mm / 12.0;
  const double scale = x_mm * u_scale_x, square = y_mm * u_squareness_rad, tilt = z_mm * u_tilt_x_rad;
  const double bow = straightness.u_dx_mm(y_mm), screw = lead.u_dx_mm(x_mm);
  return std::sqrt(step_sq + scale * scale + square * square + tilt * tilt + bow * bow + screw * screw);
}

double TablePosition::u_y_mm(double x_mm, double y_mm, double z_mm) const {
  const double scale = y_mm * u_scale_y, tilt = z_mm * u_tilt_y_rad, bow = straightness.u_dy_mm(x_mm), screw = lead.u_dy_mm(y_mm);
  return std::sqrt(step_mm * step_mm / 12.0 + scale * scale + tilt * tilt + bow * bow + screw * screw);
}

TablePosition table_position(const ScanData& scan, const std::optional<TableCalibration>& calibration) {
  TablePosition t;
  if (scan.device) t.step_mm = scan.device->axis_resolution_nm * 1e-6;
  if (calibration && calibration->has_axes) {
    t.u_scale_x = calibration->u_scale_x_ppm * 1e-6;
    t.u_scale_y = calibration->u_scale_y_ppm * 1e-6;
    t.u_squareness_rad = calibration->u_squareness_urad * 1e-6;
    t.straightness = calibration->straightness;
  }
  if (calibration) t.lead = calibration->lead;
  if (calibration && calibration->has_gauge_tilt) {
    t.u_tilt_x_rad = calibration->u_gauge_tilt_x_urad * 1e-6;
    t.u_tilt_y_rad = calibration->u_gauge_tilt_y_urad * 1e-6;
  }
  return t;
}

std::vector<std::pair<double, double>> scan_slopes(const ScanData& scan) {
  const std::vector<PointSample>& p = scan.points;
  std::vector<std::pair<double, double>> slope(p.size(), {0.0, 0.0});
  // Each line's points in scan order, and sorted along the line for the nearest-point search.
  std::map<uint32_t, std::vector<size_t>> by_line;
  for (size_t i = 0; i < p.size(); ++i) by_line[p[i].line].push_back(i);
  std::vector<std::vector<size_t>> lines;
  for (auto& [id, members] : by_line) lines.push_back(std::move(members));
  // The lines' direction: the first line with two points that differ tells (x for a raster).
  bool along_x = true;
  for (const auto& line : lines) {
    if (line.size() < 2) continue;
    const double dx = std::fabs(p[line.back()].x_nm - double(p[line.front()].x_nm));
    const double dy = std::fabs(p[line.back()].y_nm - double(p[line.front()].y_nm));
    along_x = dx >= dy;
    break;
  }
  auto along = [&](size_t i) { return along_x ? double(p[i].x_nm) : double(p[i].y_nm); };
  const SortedLines<decltype(along)> sorted(std::move(lines), along);
  for (size_t l = 0; l < sorted.size(); ++l) {
    const std::vector<size_t>& line = sorted.line(l);
    for (size_t k = 0; k < line.size(); ++k) {
      const size_t i = line[k];
      long neighbour[4] = {k > 0 ? static_cast<long>(line[k - 1]) : -1, k + 1 < line.size() ? static_cast<long>(line[k + 1]) : -1,
                           l > 0 ? sorted.nearest_on(l - 1, i) : -1, l + 1 < sorted.size() ? sorted.nearest_on(l + 1, i) : -1};
      // Least squares for the gradient g over the differences: sum (dz - g . d)^2, in mm.
      double a11 = 0, a12 = 0, a22 = 0, b1 = 0, b2 = 0;
      for (long n : neighbour) {
        if (n < 0) continue;
        const double dx = (p[static_cast<size_t>(n)].x_nm - double(p[i].x_nm)) * 1e-6;
        const double dy = (p[static_cast<size_t>(n)].y_nm - double(p[i].y_nm)) * 1e-6;
        const double dz = (p[static_cast<size_t>(n)].z_nm - double(p[i].z_nm)) * 1e-6;
        if (dx == 0 && dy == 0) continue;
        a11 += dx * dx, a12 += dx * dy, a22 += dy * dy, b1 += dx * dz, b2 += dy * dz;
      }
      const double det = a11 * a22 - a12 * a12;
      if (det > 1e-12 * (a11 + a22) * (a11 + a22)) {
        slope[i] = {(a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det};
      } else if (a11 + a22 > 0) {
        // Neighbours along one direction only (a single line, say): the slope along it.
        slope[i] = {b1 / (a11 + a22), b2 / (a11 + a22)};
      }
    }
  }
  return slope;
}

double add_position_uncertainty(const ScanData& scan, const TablePosition& table, std::vector<double>& sigma_mm) {
  if (sigma_mm.size() != scan.points.size()) return 0;
  if (!(table.step_mm > 0) && !(table.u_scale_x > 0) && !(table.u_scale_y > 0) && !(table.u_squareness_rad > 0) &&
      !(table.u_tilt_x_rad > 0) && !(table.u_tilt_y_rad > 0) && !table.straightness.measured &&
      !table.lead.measured) {
    return 0;
  }
  const std::vector<std::pair<double, double>> slope = scan_slopes(scan);
  double largest = 0;
  for (size_t i = 0; i < sigma_mm.size(); ++i) {
    const double x = scan.points[i].x_nm * 1e-6, y = scan.points[i].y_nm * 1e-6, z = scan.points[i].z_nm * 1e-6;
    const double ux = slope[i].first * table.u_x_mm(x, y, z), uy = slope[i].second * table.u_y_mm(x, y, z);
    const double added_sq = ux * ux + uy * uy;
    if (!std::isfinite(added_sq)) continue;
    sigma_mm[i] = std::sqrt(sigma_mm[i] * sigma_mm[i] + added_sq);
    largest = std::max(largest, std::sqrt(added_sq));
  }
  return largest;
}

}  // namespace dg::host
