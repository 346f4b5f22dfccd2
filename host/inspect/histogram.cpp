// Drawing the deviations' histogram as SVG: bars, axes with round ticks, the tolerance and U.
#include "host/inspect/histogram.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace dg::host {

namespace {

std::string number(double v, const char* format = "%.4g") {
  char text[32];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

// A round tick step (1, 2 or 5 times a power of ten) giving about `count` ticks over `span`.
double tick_step(double span, int count) {
  const double raw = span / count;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * power >= raw) return m * power;
  }
  return 10 * power;
}

}  // namespace

std::string deviation_histogram_svg(const Inspection& inspection, const Decision* decision, int bins) {
  const int width = 900, height = 320, left = 70, right = 20, top = 20, bottom = 50;
  const int plot_w = width - left - right, plot_h = height - top - bottom;
  double lo = 0, hi = 0;
  for (const PointDeviation& p : inspection.points) {
    lo = std::min(lo, p.distance);
    hi = std::max(hi, p.distance);
  }
  if (decision) {
    const double widen = decision->max_expanded_mm;
    lo = std::min(lo, decision->limits.lower_mm - widen);
    hi = std::max(hi, decision->limits.upper_mm + widen);
  }
  if (!(hi > lo)) {
    lo -= 0.001;
    hi += 0.001;
  }
  const double margin = 0.05 * (hi - lo);
  lo -= margin;
  hi += margin;
  bins = std::max(bins, 1);
  std::vector<size_t> count(static_cast<size_t>(bins), 0);
  for (const PointDeviation& p : inspection.points) {
    const int b = std::clamp(static_cast<int>((p.distance - lo) / (hi - lo) * bins), 0, bins - 1);
    ++count[static_cast<size_t>(b)];
  }
  const size_t most = std::max<size_t>(1, *std::max_element(count.begin(), count.end()));
  auto x_of = [&](double v) { return left + (v - lo) / (hi - lo) * plot_w; };
  auto y_of = [&](double n) { return top + plot_h - n / static_cast<double>(most) * plot_h; };
  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"histogram\" width=\"" + std::to_string(width) +
                  "\" height=\"" + std::to_string(height) + "\" viewBox=\"0 0 " + std::to_string(width) + " " +
                  std::to_string(height) + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  s += "<rect x=\"0\" y=\"0\" width=\"" + std::to_string(width) + "\" height=\"" + std::to_string(height) + "\" fill=\"white\"/>\n";
  if (decision) {
    // Inside the limits but within U of them: conformance not proven there.
    const double lower = decision->limits.lower_mm, upper = decision->limits.upper_mm, u = decision->max_expanded_mm;
    for (const auto& band : {std::pair<double, double>{lower - u, lower + u}, std::pair<double, double>{upper - u, upper + u}}) {
      s += "<rect class=\"uncertainty\" x=\"" + number(x_of(band.first), "%.2f") + "\" y=\"" + std::to_string(top) + "\" width=\"" +
           number(x_of(band.second) - x_of(band.first), "%.2f") + "\" height=\"" + std::to_string(plot_h) +
           "\" fill=\"#f6d48b\" fill-opacity=\"0.6\"/>\n";
    }
  }
  const double bar_w = static_cast<double>(plot_w) / bins;
  for (int b = 0; b < bins; ++b) {
    const size_t n = count[static_cast<size_t>(b)];
    const double y = y_of(static_cast<double>(n));
    s += "<rect class=\"bar\" data-count=\"" + std::to_string(n) + "\" x=\"" + number(left + b * bar_w, "%.2f") + "\" y=\"" +
         number(y, "%.2f") + "\" width=\"" + number(std::max(bar_w - 1, 0.5), "%.2f") + "\" height=\"" +
         number(top + plot_h - y, "%.2f") + "\" fill=\"#4a78b5\"/>\n";
  }
  if (decision) {
    for (double limit : {decision->limits.lower_mm, decision->limits.upper_mm}) {
      const std::string x = number(x_of(limit), "%.2f");
      s += "<line class=\"limit\" x1=\"" + x + "\" x2=\"" + x + "\" y1=\"" + std::to_string(top) + "\" y2=\"" +
           std::to_string(top + plot_h) + "\" stroke=\"#c62828\" stroke-width=\"2\"/>\n";
      s += "<text x=\"" + x + "\" y=\"" + std::to_string(top - 6) + "\" text-anchor=\"middle\" fill=\"#c62828\">" + number(limit) +
           "</text>\n";
    }
  }
  // Axes: deviation in mm along x, points up y.
  s += "<line x1=\"" + std::to_string(left) + "\" x2=\"" + std::to_string(left + plot_w) + "\" y1=\"" + std::to_string(top + plot_h) +
       "\" y2=\"" + std::to_string(top + plot_h) + "\" stroke=\"black\"/>\n";
  s += "<line x1=\"" + std::to_string(left) + "\" x2=\"" + std::to_string(left) + "\" y1=\"" + std::to_string(top) + "\" y2=\"" +
       std::to_string(top + plot_h) + "\" stroke=\"black\"/>\n";
  const double step = tick_step(hi - lo, 8);
  for (double t = std::ceil(lo / step) * step; t <= hi; t += step) {
    const double v = std::fabs(t) < step * 1e-6 ? 0.0 : t;
    const std::string x = number(x_of(v), "%.2f");
    s += "<line x1=\"" + x + "\" x2=\"" + x + "\" y1=\"" + std::to_string(top + plot_h) + "\" y2=\"" + std::to_string(top + plot_h + 5) +
         "\" stroke=\"black\"/>\n<text x=\"" + x + "\" y=\"" + std::to_string(top + plot_h + 18) + "\" text-anchor=\"middle\">" +
         number(v) + "</text>\n";
  }
  const double count_step = std::max(1.0, tick_step(static_cast<double>(most), 4));
  for (double n = 0; n <= static_cast<double>(most); n += count_step) {
    const std::string y = number(y_of(n), "%.2f");
    s += "<line x1=\"" + std::to_string(left - 5) + "\" x2=\"" + std::to_string(left) + "\" y1=\"" + y + "\" y2=\"" + y +
         "\" stroke=\"black\"/>\n<text x=\"" + std::to_string(left - 8) + "\" y=\"" + y + "\" dy=\"4\" text-anchor=\"end\">" +
         number(n, "%.0f") + "</text>\n";
  }
  s += "<text x=\"" + std::to_string(left + plot_w / 2) + "\" y=\"" + std::to_string(height - 8) +
       "\" text-anchor=\"middle\">signed orthogonal deviation, mm</text>\n";
  s += "<text transform=\"translate(16," + std::to_string(top + plot_h / 2) + ") rotate(-90)\" text-anchor=\"middle\">points</text>\n";
  return s + "</svg>\n";
}

}  // namespace dg::host
