// Binning, colours and the two picture formats of the deviation maps.
#include "host/inspect/deviation_map.h"
#include "host/inspect/number_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dg::host {

Rgb diverging_colour(double t) {
  t = std::clamp(std::isfinite(t) ? t : 0.0, -1.0, 1.0);
  // White at 0 to a saturated red (+1) or blue (-1).
  const double a = std::fabs(t);
  const auto c = [&](double full) { return static_cast<uint8_t>(std::lround(255.0 + (full - 255.0) * a)); };
  return t >= 0 ? Rgb{c(200), c(30), c(30)} : Rgb{c(30), c(70), c(200)};
}

namespace {

Rgb blend(Rgb a, Rgb b, double t) {
  const auto mix = [t](uint8_t x, uint8_t y) { return static_cast<uint8_t>(std::lround(x + (y - x) * t)); };
  return Rgb{mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b)};
}

}  // namespace

Rgb tolerance_colour(double value_mm, double lower_mm, double upper_mm) {
  if (!std::isfinite(value_mm)) value_mm = 0;
  if (value_mm > upper_mm) return kAboveUpperLimit;
  if (value_mm < lower_mm) return kBelowLowerLimit;
  const double nominal = lower_mm < 0 && upper_mm > 0 ? 0.0 : 0.5 * (lower_mm + upper_mm);
  const bool above = value_mm >= nominal;
  const double reach = above ? upper_mm - nominal : nominal - lower_mm;
  const double t = reach > 0 ? std::clamp(std::fabs(value_mm - nominal) / reach, 0.0, 1.0) : 1.0;
  // Green over the middle quarter of each half, then to the half's middle colour at 0.6 of the way
  // and its full colour at the limit.
  const Rgb green{40, 160, 75}, middle = above ? Rgb{235, 200, 30} : Rgb{30, 180, 200},
            limit = above ? Rgb{215, 35, 35} : Rgb{30, 75, 205};
  if (t <= 0.25) return green;
  if (t <= 0.6) return blend(green, middle, (t - 0.25) / 0.35);
  return blend(middle, limit, (t - 0.6) / 0.4);
}

Rgb scale_colour(const ColourScale& scale, double range_mm, double value_mm) {
  if (scale.tolerance()) return tolerance_colour(value_mm, scale.lower_mm, scale.upper_mm);
  return diverging_colour(value_mm / range_mm);
}

namespace {

struct Layout {
  // The part's area: left and bottom margins hold the SVG's mm axes.
  int plot_x = 74, plot_y = 20, plot_w = 0, plot_h = 0;
  int bar_x = 0, bar_y = 40, bar_w = 28, bar_h = 0;  // the colour bar
  double x0 = 0, y0 = 0, mm_to_px = 1;                // table mm to pixels
  double range = 1;
  int cell = 2;             // pixels per bin
  int columns = 1, rows = 1;  // bins; the frame is exactly columns x rows cells
};

Layout layout(const std::vector<MapPoint>& points, const MapPicture& pic) {
  Layout l;
  const int bar_area = 210, axis_below = 52;
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  if (!points.empty()) {
    x_min = x_max = points[0].x_mm;
    y_min = y_max = points[0].y_mm;
    for (const MapPoint& p : points) {
      x_min = std::min(x_min, p.x_mm), x_max = std::max(x_max, p.x_mm);
      y_min = std::min(y_min, p.y_mm), y_max = std::max(y_max, p.y_mm);
    }
  }
  const double span_x = std::max(x_max - x_min, 1e-9), span_y = std::max(y_max - y_min, 1e-9);
  const int room_w = pic.width - bar_area - l.plot_x - 10, room_h = pic.height - l.plot_y - axis_below;
  double largest = 0;
  for (const MapPoint& p : points) largest = p.muted ? largest : std::max(largest, std::fabs(p.value_mm));
  l.range = pic.scale.range_mm > 0 ? pic.scale.range_mm : (largest > 0 ? largest : 1e-3);
  // Bins about as wide as the points' spacing, at least 2 pixels; the plot is whole bins, and the
  // scale puts the last point inside the last bin, so no strip of empty frame is left at the edges.
  const double scale = std::min(room_w / span_x, room_h / span_y);
  const double per_point =
      points.empty() ? 4.0 : std::sqrt((span_x * scale + 1) * (span_y * scale + 1) / static_cast<double>(points.size()));
  l.cell = std::max(2, static_cast<int>(std::ceil(per_point)));
  l.columns = std::max(1, static_cast<int>(room_w / l.cell));
  l.rows = std::max(1, static_cast<int>(room_h / l.cell));
  l.mm_to_px = std::min((l.columns - 1) * l.cell / span_x, (l.rows - 1) * l.cell / span_y);
  l.columns = std::min(l.columns, static_cast<int>(span_x * l.mm_to_px) / l.cell + 1);
  l.rows = std::min(l.rows, static_cast<int>(span_y * l.mm_to_px) / l.cell + 1);
  l.plot_w = l.columns * l.cell;
  l.plot_h = l.rows * l.cell;
  l.x0 = x_min;
  l.y0 = y_min;
  l.bar_x = pic.width - bar_area + 20;
  l.bar_h = pic.height - 2 * l.bar_y;
  return l;
}

struct Bin {
  double value = 0;
  bool used = false;
  bool muted = false;  // holds muted points only
};

Rgb bin_colour(const Bin& b, const MapPicture& pic, double range_mm) {
  return b.muted ? kMutedColour : scale_colour(pic.scale, range_mm, b.value);
}

// The largest-|value| point of each bin, on the layout's grid of `cell`-pixel bins.
std::vector<Bin> bin(const std::vector<MapPoint>& points, const Layout& l) {
  const int columns = l.columns, rows = l.rows;
  std::vector<Bin> bins(static_cast<size_t>(columns) * rows);
  for (const MapPoint& p : points) {
    const int c = std::clamp(static_cast<int>((p.x_mm - l.x0) * l.mm_to_px) / l.cell, 0, columns - 1);
    // The table's y grows upwards; the picture's downwards.
    const int r = std::clamp(static_cast<int>((p.y_mm - l.y0) * l.mm_to_px) / l.cell, 0, rows - 1);
    Bin& b = bins[static_cast<size_t>(rows - 1 - r) * columns + c];
    // A point on the scale wins over muted ones; among its kind the largest |value|.
    if (b.used && p.muted && !b.muted) continue;
    if (!b.used || (b.muted && !p.muted) || std::fabs(p.value_mm) > std::fabs(b.value)) b.value = p.value_mm;
    b.muted = p.muted;
    b.used = true;
  }
  // Bins and point spacing rarely match to the pixel, which leaves empty stripes in a regular
  // grid: an empty bin between used ones takes its neighbour's value (one pass, so real holes in
  // the scan stay visible).
  std::vector<Bin> filled = bins;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c) {
      if (bins[static_cast<size_t>(r) * columns + c].used) continue;
      auto used = [&](int rr, int cc) {
        return rr >= 0 && rr < rows && cc >= 0 && cc < columns && bins[static_cast<size_t>(rr) * columns + cc].used;
      };
      const bool across = used(r, c - 1) && used(r, c + 1), down = used(r - 1, c) && used(r + 1, c);
      if (across) filled[static_cast<size_t>(r) * columns + c] = bins[static_cast<size_t>(r) * columns + c - 1];
      else if (down) filled[static_cast<size_t>(r) * columns + c] = bins[static_cast<size_t>(r - 1) * columns + c];
    }
  return filled;
}

// A tick step of 1, 2 or 5 times a power of ten that gives about `count` ticks over `span`.
double tick_step(double span, int count) {
  const double raw = span / std::max(1, count);
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * power >= raw) return m * power;
  }
  return 10 * power;
}

// The table's x and y in mm along the plot's bottom and left edges: a point at x lies in the bin
// that starts (x - x0) * mm_to_px pixels in, so a tick marks the middle of that bin.
std::string axes_svg(const Layout& l) {
  std::string out;
  char buffer[320];
  const double span_x = (l.columns - 1) * l.cell / l.mm_to_px, span_y = (l.rows - 1) * l.cell / l.mm_to_px;
  const double step_x = tick_step(span_x, 8), step_y = tick_step(span_y, 6);
  const int bottom = l.plot_y + l.plot_h;
  for (double x = std::ceil(l.x0 / step_x) * step_x; x <= l.x0 + span_x + 1e-9 * step_x; x += step_x) {
    const double px = l.plot_x + (x - l.x0) * l.mm_to_px + 0.5 * l.cell;
    std::snprintf(buffer, sizeof buffer,
                  "<line x1=\"%.1f\" y1=\"%d\" x2=\"%.1f\" y2=\"%d\" stroke=\"#141414\"/>"
                  "<text x=\"%.1f\" y=\"%d\" font-family=\"sans-serif\" font-size=\"13\" text-anchor=\"middle\">%g</text>\n",
                  px, bottom, px, bottom + 5, px, bottom + 19, std::fabs(x) < 1e-9 * step_x ? 0.0 : x);
    out += buffer;
  }
  for (double y = std::ceil(l.y0 / step_y) * step_y; y <= l.y0 + span_y + 1e-9 * step_y; y += step_y) {
    const double py = bottom - (y - l.y0) * l.mm_to_px - 0.5 * l.cell;
    std::snprintf(buffer, sizeof buffer,
                  "<line x1=\"%d\" y1=\"%.1f\" x2=\"%d\" y2=\"%.1f\" stroke=\"#141414\"/>"
                  "<text x=\"%d\" y=\"%.1f\" font-family=\"sans-serif\" font-size=\"13\" text-anchor=\"end\" "
                  "dominant-baseline=\"middle\">%g</text>\n",
                  l.plot_x - 5, py, l.plot_x, py, l.plot_x - 8, py, std::fabs(y) < 1e-9 * step_y ? 0.0 : y);
    out += buffer;
  }
  std::snprintf(buffer, sizeof buffer,
                "<text x=\"%d\" y=\"%d\" font-family=\"sans-serif\" font-size=\"13\" text-anchor=\"middle\">x, mm</text>\n"
                "<text x=\"%d\" y=\"%d\" font-family=\"sans-serif\" font-size=\"13\" text-anchor=\"middle\" "
                "transform=\"rotate(-90 %d %d)\">y, mm</text>\n",
                l.plot_x + l.plot_w / 2, bottom + 40, 22, l.plot_y + l.plot_h / 2, 22, l.plot_y + l.plot_h / 2);
  out += buffer;
  return out;
}

std::string mm_label(double v) { return number_text(v, "%+.4f") + " mm"; }

// Text for an SVG element.
std::string xml_text(const std::string& s) {
  std::string out;
  for (char ch : s) out += ch == '<' ? std::string("&lt;") : ch == '>' ? std::string("&gt;") : ch == '&' ? std::string("&amp;") : std::string(1, ch);
  return out;
}

// The colour bar, top to bottom. A tolerance scale holds the out-of-tolerance colours in blocks of
// kLimitBlock of its height above and below the ramp between the limits.
constexpr double kLimitBlock = 0.08;

// The colour at `from_top` (0 the bar's top, 1 its bottom).
Rgb bar_colour(const ColourScale& s, double from_top) {
  if (s.tolerance()) {
    if (from_top < kLimitBlock) return kAboveUpperLimit;
    if (from_top > 1 - kLimitBlock) return kBelowLowerLimit;
    const double f = (from_top - kLimitBlock) / (1 - 2 * kLimitBlock);
    return tolerance_colour(s.upper_mm - f * (s.upper_mm - s.lower_mm), s.lower_mm, s.upper_mm);
  }
  return diverging_colour(s.magnitude ? 1.0 - from_top : 1.0 - 2.0 * from_top);
}

struct BarLabel {
  double from_top;
  std::string text;
};

// Five values down the ramp; a tolerance scale also names its two blocks.
std::vector<BarLabel> bar_labels(const ColourScale& s, double range) {
  std::vector<BarLabel> out;
  if (s.tolerance()) {
    out.push_back({0.5 * kLimitBlock, "> " + mm_label(s.upper_mm)});
    for (int k = 0; k <= 4; ++k) {
      out.push_back({kLimitBlock + (1 - 2 * kLimitBlock) * k / 4.0, mm_label(s.upper_mm - (s.upper_mm - s.lower_mm) * k / 4.0)});
    }
    out.push_back({1 - 0.5 * kLimitBlock, "< " + mm_label(s.lower_mm)});
    return out;
  }
  for (int k = 0; k <= 4; ++k) out.push_back({k / 4.0, mm_label(s.magnitude ? range * (1.0 - k / 4.0) : range * (1.0 - k / 2.0))});
  return out;
}

}  // namespace

std::string deviation_map_png(const std::vector<MapPoint>& points, const MapPicture& pic) {
  const Layout l = layout(points, pic);
  Raster image(pic.width, pic.height, Rgb{255, 255, 255});
  const Rgb grey{120, 120, 120}, black{20, 20, 20};
  // The part's frame, then its bins.
  image.fill(l.plot_x - 1, l.plot_y - 1, l.plot_x + l.plot_w + 1, l.plot_y + l.plot_h + 1, grey);
  image.fill(l.plot_x, l.plot_y, l.plot_x + l.plot_w, l.plot_y + l.plot_h, Rgb{235, 235, 235});
  const int columns = l.columns, rows = l.rows;
  const std::vector<Bin> bins = bin(points, l);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c) {
      const Bin& b = bins[static_cast<size_t>(r) * columns + c];
      if (!b.used) continue;
      const int x = l.plot_x + c * l.cell, y = l.plot_y + r * l.cell;
      image.fill(x, y, x + l.cell, y + l.cell, bin_colour(b, pic, l.range));
    }
  // The colour bar: +range at the top, -range (or 0 for a magnitude) at the bottom, or the limits
  // and the blocks beyond them; its labels.
  for (int y = 0; y < l.bar_h; ++y) {
    const double from_top = static_cast<double>(y) / std::max(1, l.bar_h - 1);
    image.fill(l.bar_x, l.bar_y + y, l.bar_x + l.bar_w, l.bar_y + y + 1, bar_colour(pic.scale, from_top));
  }
  for (const BarLabel& label : bar_labels(pic.scale, l.range)) {
    const int y = l.bar_y + static_cast<int>(std::lround((l.bar_h - 1) * label.from_top));
    image.fill(l.bar_x + l.bar_w, y, l.bar_x + l.bar_w + 6, y + 1, black);
    image.text(l.bar_x + l.bar_w + 10, y - 7, label.text, black, 2);
  }
  return image.png();
}

std::string deviation_map_svg(const std::vector<MapPoint>& points, const MapPicture& pic, const std::string& title) {
  const Layout l = layout(points, pic);
  const int columns = l.columns, rows = l.rows;
  const std::vector<Bin> bins = bin(points, l);
  std::string out;
  char buffer[256];
  std::snprintf(buffer, sizeof buffer,
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\">\n", pic.width,
                pic.height, pic.width, pic.height);
  out += buffer;
  out += "<title>" + xml_text(title) + "</title>\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  std::snprintf(buffer, sizeof buffer, "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"#ebebeb\" stroke=\"#787878\"/>\n",
                l.plot_x, l.plot_y, l.plot_w, l.plot_h);
  out += buffer;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c) {
      const Bin& b = bins[static_cast<size_t>(r) * columns + c];
      if (!b.used) continue;
      const Rgb col = bin_colour(b, pic, l.range);
      std::snprintf(buffer, sizeof buffer, "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"#%02x%02x%02x\"/>\n",
                    l.plot_x + c * l.cell, l.plot_y + r * l.cell, l.cell, l.cell, col.r, col.g, col.b);
      out += buffer;
    }
  out += axes_svg(l);
  // The colour bar: a gradient through the same colours as the cells, sampled finely enough that
  // the tolerance scale's green band and the edges of its out-of-tolerance blocks stay sharp.
  out += "<defs><linearGradient id=\"bar\" x1=\"0\" y1=\"0\" x2=\"0\" y2=\"1\">";
  constexpr int kStops = 200;
  for (int k = 0; k <= kStops; ++k) {
    const Rgb col = bar_colour(pic.scale, static_cast<double>(k) / kStops);
    std::snprintf(buffer, sizeof buffer, "<stop offset=\"%.3f\" stop-color=\"#%02x%02x%02x\"/>", static_cast<double>(k) / kStops,
                  col.r, col.g, col.b);
    out += buffer;
  }
  out += "</linearGradient></defs>\n";
  std::snprintf(buffer, sizeof buffer, "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"url(#bar)\"/>\n", l.bar_x, l.bar_y,
                l.bar_w, l.bar_h);
  out += buffer;
  for (const BarLabel& label : bar_labels(pic.scale, l.range)) {
    const int y = l.bar_y + static_cast<int>(std::lround((l.bar_h - 1) * label.from_top));
    const std::string text = xml_text(label.text);
    std::snprintf(buffer, sizeof buffer,
                  "<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"#141414\"/>"
                  "<text x=\"%d\" y=\"%d\" font-family=\"sans-serif\" font-size=\"14\" dominant-baseline=\"middle\">%s</text>\n",
                  l.bar_x + l.bar_w, y, l.bar_x + l.bar_w + 5, y, l.bar_x + l.bar_w + 8, y, text.c_str());
    out += buffer;
  }
  out += "</svg>\n";
  return out;
}

}  // namespace dg::host
