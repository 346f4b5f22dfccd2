// Latch-delay estimation over a fly scan's serpentine lines, the positions it corrects, and the
// lifted readings it takes out.
#include "host/scan/fly_correction.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <tuple>

#include "common/proto/scan_grid.h"

namespace dg::host {
namespace {

bool lifted(const PointSample& p) { return (p.flags & digitizer_PointFlag_POINT_LIFTED) != 0; }

// One line's points in time order: where the table was at each request, its speed there.
struct FlyLine {
  std::vector<size_t> index;   // into scan.points
  std::vector<double> x_mm;    // the table's position at the request
  std::vector<double> v_mm_s;  // the line's speed there (signed)
  std::vector<double> z_mm;
  std::vector<bool> usable;    // not lifted
};

// Position and speed at each request. The table stands on a whole step at every moment, and the
// step count at the request is where it stood then: the position stays as sent. The speed is the
// average over the time to the next request (to the previous one for a line's last point, or where
// the next came after a pause: a line flown again after a gap, whose first flight ended there), so
// that the position `delay` later is interpolated between two requests of one flight, which
// follows the table as it speeds up or slows down at a line's end as well as at constant feed. A
// point with neither neighbour in its flight takes the line's median speed.
void positions_and_speeds(const std::vector<PointSample>& points, FlyLine* line) {
  const size_t n = line->index.size();
  line->x_mm.resize(n);
  line->v_mm_s.assign(n, 0.0);
  std::vector<double> dt_s(n > 0 ? n - 1 : 0), speeds;
  for (size_t i = 0; i + 1 < n; ++i) {
    const PointSample& a = points[line->index[i]];
    const PointSample& b = points[line->index[i + 1]];
    dt_s[i] = (static_cast<double>(b.t_us) - static_cast<double>(a.t_us)) * 1e-6;
    if (dt_s[i] > 0) speeds.push_back((b.x_nm - a.x_nm) * 1e-6 / dt_s[i]);
  }
  std::vector<double> sorted_dt = dt_s;
  std::sort(sorted_dt.begin(), sorted_dt.end());
  const double usual_dt = sorted_dt.empty() ? 0 : sorted_dt[sorted_dt.size() / 2];
  std::sort(speeds.begin(), speeds.end());
  const double line_speed = speeds.empty() ? 0 : speeds[speeds.size() / 2];
  auto same_flight = [&](size_t gap) { return dt_s[gap] > 0 && dt_s[gap] <= 2.5 * usual_dt; };
  auto speed = [&](size_t gap) {
    const PointSample& a = points[line->index[gap]];
    const PointSample& b = points[line->index[gap + 1]];
    return (b.x_nm - a.x_nm) * 1e-6 / dt_s[gap];
  };
  for (size_t i = 0; i < n; ++i) {
    line->x_mm[i] = points[line->index[i]].x_nm * 1e-6;
    if (i + 1 < n && same_flight(i)) {
      line->v_mm_s[i] = speed(i);
    } else if (i > 0 && same_flight(i - 1)) {
      line->v_mm_s[i] = speed(i - 1);
    } else {
      line->v_mm_s[i] = line_speed;
    }
  }
}

// A line's usable points at positions shifted by its speed times `delay_s`, sorted by x for
// lookups, each with its place in the line so that no lookup bridges a reading left out.
struct Profile {
  std::vector<double> x, z;
  std::vector<size_t> at;
};

Profile shifted_profile(const FlyLine& line, double delay_s) {
  std::vector<std::tuple<double, double, size_t>> xz;
  for (size_t i = 0; i < line.x_mm.size(); ++i) {
    if (line.usable[i]) xz.emplace_back(line.x_mm[i] + line.v_mm_s[i] * delay_s, line.z_mm[i], i);
  }
  std::sort(xz.begin(), xz.end());
  Profile p;
  for (const auto& [x, z, i] : xz) p.x.push_back(x), p.z.push_back(z), p.at.push_back(i);
  return p;
}

// Linear interpolation between two neighbouring readings of the line; false outside the line or
// across a gap.
bool profile_at(const Profile& p, double x, double* z) {
  if (p.x.size() < 2 || x < p.x.front() || x > p.x.back()) return false;
  const size_t k = static_cast<size_t>(std::upper_bound(p.x.begin(), p.x.end(), x) - p.x.begin());
  const size_t b = std::min(k, p.x.size() - 1), a = b - 1;
  if (p.at[a] + 1 != p.at[b] && p.at[b] + 1 != p.at[a]) return false;
  const double span = p.x[b] - p.x[a];
  const double w = span > 0 ? (x - p.x[a]) / span : 0;
  *z = p.z[a] + w * (p.z[b] - p.z[a]);
  return true;
}

constexpr size_t kAllLines = SIZE_MAX;

// The mismatch of every line with its neighbours at one delay (or of line `only`'s): each point's
// residual against the mean of its two neighbour lines (or the one, in a scan of two lines).
std::vector<double> residuals(const std::vector<FlyLine>& lines, double delay_s, size_t only = kAllLines) {
  const size_t n = lines.size();
  std::vector<Profile> profiles(n);
  for (size_t k = 0; k < n; ++k) {
    if (only == kAllLines || (k + 1 >= only && k <= only + 1)) profiles[k] = shifted_profile(lines[k], delay_s);
  }
  std::vector<double> r;
  for (size_t k = 0; k < n; ++k) {
    if (only != kAllLines && k != only) continue;
    if (n > 2 && (k == 0 || k + 1 == n)) continue;
    if (n == 2 && k == 1) continue;
    const FlyLine& line = lines[k];
    for (size_t i = 0; i < line.x_mm.size(); ++i) {
      if (!line.usable[i]) continue;
      const double x = line.x_mm[i] + line.v_mm_s[i] * delay_s;
      double za = 0, zb = 0;
      if (n == 2) {
        if (profile_at(profiles[1], x, &za)) r.push_back(line.z_mm[i] - za);
      } else if (profile_at(profiles[k - 1], x, &za) && profile_at(profiles[k + 1], x, &zb)) {
        r.push_back(line.z_mm[i] - 0.5 * (za + zb));
      }
    }
  }
  return r;
}

double sum_of_squares(const std::vector<double>& r) {
  double s = 0;
  for (double v : r) s += v * v;
  return s;
}

// The mean square residual, comparable across delays that pair different numbers of points.
double mismatch(const std::vector<FlyLine>& lines, double delay_s, size_t only) {
  const std::vector<double> r = residuals(lines, delay_s, only);
  return r.size() < 3 ? INFINITY : sum_of_squares(r) / static_cast<double>(r.size());
}

// The delay that fits best: a search over a cycle before the request to one after it, then golden
// sections in the best bracket.
double best_delay(const std::vector<FlyLine>& lines, double cycle_s, size_t only) {
  constexpr int kSteps = 80;
  double best_s = 0, best = INFINITY;
  for (int k = -kSteps / 2; k <= kSteps; ++k) {
    const double d = cycle_s * k / kSteps;
    const double m = mismatch(lines, d, only);
    if (m < best) best = m, best_s = d;
  }
  if (!std::isfinite(best)) return NAN;
  double a = best_s - cycle_s / kSteps, b = best_s + cycle_s / kSteps;
  const double g = (std::sqrt(5.0) - 1) / 2;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = mismatch(lines, c, only), fd = mismatch(lines, d, only);
  for (int it = 0; it < 30; ++it) {
    if (fc < fd) {
      b = d, d = c, fd = fc, c = b - g * (b - a), fc = mismatch(lines, c, only);
    } else {
      a = c, c = d, fc = fd, d = a + g * (b - a), fd = mismatch(lines, d, only);
    }
  }
  return 0.5 * (a + b);
}

double median_of(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

}  // namespace

std::optional<FlyCorrection> correct_fly_scan(ScanData& scan, std::vector<double>* sigma_mm, const std::string& name,
                                              bool drop_lifted) {
  if (!scan.request || !flies(*scan.request)) return std::nullopt;
  std::vector<FlyLine> lines;
  std::vector<uint32_t> line_numbers;
  for (size_t i = 0; i < scan.points.size(); ++i) {
    const PointSample& p = scan.points[i];
    if (line_numbers.empty() || line_numbers.back() != p.line) {
      line_numbers.push_back(p.line);
      lines.emplace_back();
    }
    lines.back().index.push_back(i);
    lines.back().z_mm.push_back(p.z_nm * 1e-6);
    lines.back().usable.push_back(!lifted(p));
  }
  // A reading next to a lifted one may have been taken as the plunger left the part or landed on
  // it again, short of the flag's threshold: the delay is measured without them too.
  for (auto& line : lines) {
    const std::vector<bool> own = line.usable;
    for (size_t i = 0; i < own.size(); ++i) {
      for (size_t j = i >= 2 ? i - 2 : 0; j <= i + 2 && j < own.size(); ++j) {
        if (!own[j]) line.usable[i] = false;
      }
    }
  }
  std::vector<FlyLine> measured;  // lines of at least three points
  std::vector<double> dt_s, spacing_mm, feed_mm_s;
  for (auto& line : lines) {
    positions_and_speeds(scan.points, &line);
    for (size_t i = 1; i < line.index.size(); ++i) {
      dt_s.push_back(static_cast<double>(scan.points[line.index[i]].t_us - scan.points[line.index[i - 1]].t_us) * 1e-6);
      spacing_mm.push_back(std::fabs(line.x_mm[i] - line.x_mm[i - 1]));
    }
    for (double v : line.v_mm_s) feed_mm_s.push_back(std::fabs(v));
    if (line.index.size() >= 3) measured.push_back(line);
  }
  if (measured.size() < 2) {
    throw std::invalid_argument(name + ": a scan on the fly needs two lines of three points or more to measure the "
                                       "gauge's latch delay; it has " + std::to_string(measured.size()));
  }
  // The delay lies between the request and the reading's arrival: searched from a cycle before to
  // one after.
  const double cycle_s = std::max(median_of(dt_s), 1e-4);
  const double delay_s = best_delay(measured, cycle_s, kAllLines);
  if (!std::isfinite(delay_s)) {
    throw std::invalid_argument(name + ": the lines of this scan on the fly do not overlap enough to measure the gauge's latch delay");
  }
  // Its uncertainty: the residuals' variance over the sum of their squared derivatives in the delay.
  const std::vector<double> r0 = residuals(measured, delay_s);
  const double h = cycle_s * 1e-3;
  const std::vector<double> rp = residuals(measured, delay_s + h), rm = residuals(measured, delay_s - h);
  double derivative_sq = 0;
  if (rp.size() == r0.size() && rm.size() == r0.size()) {
    for (size_t i = 0; i < r0.size(); ++i) derivative_sq += std::pow((rp[i] - rm[i]) / (2 * h), 2);
  }
  const double variance = r0.size() > 1 ? sum_of_squares(r0) / static_cast<double>(r0.size() - 1) : 0;
  // Lines that barely slope cannot see the delay: then it is as uncertain as a whole cycle.
  double u_delay_s = derivative_sq > 0 ? std::min(std::sqrt(variance / derivative_sq), cycle_s) : cycle_s;
  // Neighbouring residuals are not independent (a crease, a lifted stretch, the part's curvature
  // across the lines), so the formula above can be too small: the scatter of the lines' own
  // estimates (robust: 1.4826 times their median absolute deviation) over the root of their
  // number bounds it from below.
  std::vector<double> per_line;
  for (size_t k = 1; k + 1 < measured.size(); ++k) {
    const double d = best_delay(measured, cycle_s, k);
    if (std::isfinite(d)) per_line.push_back(d);
  }
  if (per_line.size() >= 3) {
    const double mid = median_of(per_line);
    std::vector<double> deviation;
    for (double d : per_line) deviation.push_back(std::fabs(d - mid));
    const double spread_s = 1.4826 * median_of(deviation) / std::sqrt(static_cast<double>(per_line.size()));
    u_delay_s = std::min(std::max(u_delay_s, spread_s), cycle_s);
  }

  FlyCorrection fix;
  fix.latch_delay_ms = delay_s * 1e3;
  fix.u_latch_delay_ms = u_delay_s * 1e3;
  fix.lines = measured.size();
  fix.feed_mm_s = median_of(feed_mm_s);
  fix.spacing_mm = median_of(spacing_mm);
  const bool have_sigma = sigma_mm != nullptr && sigma_mm->size() == scan.points.size();
  for (const auto& line : lines) {
    const size_t n = line.index.size();
    for (size_t i = 0; i < n; ++i) {
      PointSample& p = scan.points[line.index[i]];
      const double x_mm = line.x_mm[i] + line.v_mm_s[i] * delay_s;
      const double u_shift_mm = std::fabs(line.v_mm_s[i]) * u_delay_s;
      fix.u_shift_mm = std::max(fix.u_shift_mm, u_shift_mm);
      if (have_sigma && n >= 2) {
        // The shift's uncertainty reaches the height through the part's slope along the line.
        const size_t a_i = i > 0 ? i - 1 : i, b_i = i + 1 < n ? i + 1 : i;
        const double run = line.x_mm[b_i] - line.x_mm[a_i];
        const double slope = run != 0 ? (line.z_mm[b_i] - line.z_mm[a_i]) / run : 0;
        double& s = (*sigma_mm)[line.index[i]];
        s = std::sqrt(s * s + slope * slope * u_shift_mm * u_shift_mm);
      }
      p.x_nm = static_cast<int32_t>(std::llround(x_mm * 1e6));
    }
  }
  // The lifted readings: counted, their lines named, and taken out where asked.
  std::vector<PointSample> kept;
  std::vector<double> kept_sigma;
  for (size_t i = 0; i < scan.points.size(); ++i) {
    const PointSample& p = scan.points[i];
    if (lifted(p)) {
      ++fix.lifted;
      if (fix.lifted_lines.empty() || fix.lifted_lines.back() != p.line) fix.lifted_lines.push_back(p.line);
      if (drop_lifted) continue;
    }
    kept.push_back(p);
    if (have_sigma) kept_sigma.push_back((*sigma_mm)[i]);
  }
  scan.points = std::move(kept);
  if (have_sigma) *sigma_mm = std::move(kept_sigma);
  return fix;
}

std::string fly_summary(const FlyCorrection& fix) {
  char text[320];
  std::snprintf(text, sizeof text,
                "on the fly at %.2f mm/s, a point every %.3f mm: the gauge's latch delay %.3f ms (u %.3f ms) measured "
                "over %zu lines and corrected (adds u <= %.4f mm along x)",
                fix.feed_mm_s, fix.spacing_mm, fix.latch_delay_ms, fix.u_latch_delay_ms, fix.lines, fix.u_shift_mm);
  std::string out = text;
  if (fix.lifted > 0) {
    out += "; " + std::to_string(fix.lifted) + " readings where the plunger could not follow the part (lifted) left out, on line";
    out += fix.lifted_lines.size() > 1 ? "s" : "";
    for (size_t k = 0; k < fix.lifted_lines.size() && k < 12; ++k) out += (k ? ", " : " ") + std::to_string(fix.lifted_lines[k]);
    if (fix.lifted_lines.size() > 12) out += ", ...";
  } else {
    out += "; no reading lifted";
  }
  return out;
}

}  // namespace dg::host
