// Binning, colours and the two picture formats of the deviation maps.
#include "host/inspect/deviation_map.h"

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

struct Layout {
  int plot_x = 20, plot_y = 20, plot_w = 0, plot_h = 0;  // the part's area
  int bar_x = 0, bar_y = 40, bar_w = 28, bar_h = 0;      // the colour bar
  double x0 = 0, y0 = 0, mm_to_px = 1;                    // table mm to pixels
  double range = 1;
  int cell = 2;  // pixels per bin
};

Layout layout(const std::vector<MapPoint>& points, const MapPicture& pic) {
  Layout l;
  const int bar_area = 210;
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
  const int room_w = pic.width - bar_area - 2 * l.plot_x, room_h = pic.height - 2 * l.plot_y;
  l.mm_to_px = std::min(room_w / span_x, room_h / span_y);
  l.plot_w = static_cast<int>(span_x * l.mm_to_px);
  l.plot_h = static_cast<int>(span_y * l.mm_to_px);
  l.x0 = x_min;
  l.y0 = y_min;
  l.bar_x = pic.width - bar_area + 20;
  l.bar_h = pic.height - 2 * l.bar_y;
  double largest = 0;
  for (const MapPoint& p : points) largest = std::max(largest, std::fabs(p.value_mm));
  l.range = pic.range_mm > 0 ? pic.range_mm : (largest > 0 ? largest : 1e-3);
  // Bins about as wide as the points' spacing, at least 2 pixels.
  const double per_point = points.empty() ? 4.0 : std::sqrt(static_cast<double>(l.plot_w + 1) * (l.plot_h + 1) / static_cast<double>(points.size()));
  l.cell = std::max(2, static_cast<int>(std::ceil(per_point)));
  return l;
}

struct Bin {
  double value = 0;
  bool used = false;
};

// The largest-|value| point of each bin, on a grid of `cell`-pixel bins over the plot.
std::vector<Bin> bin(const std::vector<MapPoint>& points, const Layout& l, int& columns, int& rows) {
  columns = l.plot_w / l.cell + 1;
  rows = l.plot_h / l.cell + 1;
  std::vector<Bin> bins(static_cast<size_t>(columns) * rows);
  for (const MapPoint& p : points) {
    const int c = std::clamp(static_cast<int>((p.x_mm - l.x0) * l.mm_to_px) / l.cell, 0, columns - 1);
    // The table's y grows upwards; the picture's downwards.
    const int r = std::clamp(static_cast<int>((p.y_mm - l.y0) * l.mm_to_px) / l.cell, 0, rows - 1);
    Bin& b = bins[static_cast<size_t>(rows - 1 - r) * columns + c];
    if (!b.used || std::fabs(p.value_mm) > std::fabs(b.value)) b.value = p.value_mm;
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

std::string mm_label(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%+.4f mm", v);
  return text;
}

}  // namespace

std::string deviation_map_png(const std::vector<MapPoint>& points, const MapPicture& pic) {
  const Layout l = layout(points, pic);
  Raster image(pic.width, pic.height, Rgb{255, 255, 255});
  const Rgb grey{120, 120, 120}, black{20, 20, 20};
  // The part's frame, then its bins.
  image.fill(l.plot_x - 1, l.plot_y - 1, l.plot_x + l.plot_w + l.cell + 1, l.plot_y + l.plot_h + l.cell + 1, grey);
  image.fill(l.plot_x, l.plot_y, l.plot_x + l.plot_w + l.cell, l.plot_y + l.plot_h + l.cell, Rgb{235, 235, 235});
  int columns = 0, rows = 0;
  const std::vector<Bin> bins = bin(points, l, columns, rows);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c) {
      const Bin& b = bins[static_cast<size_t>(r) * columns + c];
      if (!b.used) continue;
      const int x = l.plot_x + c * l.cell, y = l.plot_y + r * l.cell;
      image.fill(x, y, x + l.cell, y + l.cell, diverging_colour(b.value / l.range));
    }
  // The colour bar: +range at the top, -range (or 0 for a magnitude) at the bottom, five labels.
  for (int y = 0; y < l.bar_h; ++y) {
    const double from_top = static_cast<double>(y) / std::max(1, l.bar_h - 1);
    const double t = pic.magnitude ? 1.0 - from_top : 1.0 - 2.0 * from_top;
    image.fill(l.bar_x, l.bar_y + y, l.bar_x + l.bar_w, l.bar_y + y + 1, diverging_colour(t));
  }
  for (int k = 0; k <= 4; ++k) {
    const int y = l.bar_y + (l.bar_h - 1) * k / 4;
    image.fill(l.bar_x + l.bar_w, y, l.bar_x + l.bar_w + 6, y + 1, black);
    const double value = pic.magnitude ? l.range * (1.0 - k / 4.0) : l.range * (1.0 - k / 2.0);
    image.text(l.bar_x + l.bar_w + 10, y - 7, mm_label(value), black, 2);
  }
  return image.png();
}

std::string deviation_map_svg(const std::vector<MapPoint>& points, const MapPicture& pic, const std::string& title) {
  const Layout l = layout(points, pic);
  int columns = 0, rows = 0;
  const std::vector<Bin> bins = bin(points, l, columns, rows);
  std::string out;
  char buffer[256];
  std::snprintf(buffer, sizeof buffer,
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\">\n", pic.width,
                pic.height, pic.width, pic.height);
  out += buffer;
  std::string escaped;
  for (char ch : title) escaped += ch == '<' ? std::string("&lt;") : ch == '&' ? std::string("&amp;") : std::string(1, ch);
  out += "<title>" + escaped + "</title>\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  std::snprintf(buffer, sizeof buffer, "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"#ebebeb\" stroke=\"#787878\"/>\n",
                l.plot_x, l.plot_y, l.plot_w + l.cell, l.plot_h + l.cell);
  out += buffer;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c) {
      const Bin& b = bins[static_cast<size_t>(r) * columns + c];
      if (!b.used) continue;
      const Rgb col = diverging_colour(b.value / l.range);
      std::snprintf(buffer, sizeof buffer, "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"#%02x%02x%02x\"/>\n",
                    l.plot_x + c * l.cell, l.plot_y + r * l.cell, l.cell, l.cell, col.r, col.g, col.b);
      out += buffer;
    }
  out += "<defs><linearGradient id=\"bar\" x1=\"0\" y1=\"0\" x2=\"0\" y2=\"1\">";
  for (int k = 0; k <= 10; ++k) {
    const Rgb col = diverging_colour(1.0 - k / 5.0);
    std::snprintf(buffer, sizeof buffer, "<stop offset=\"%.1f\" stop-color=\"#%02x%02x%02x\"/>", k / 10.0, col.r, col.g, col.b);
    out += buffer;
  }
  out += "</linearGradient></defs>\n";
  std::snprintf(buffer, sizeof buffer, "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"url(#bar)\"/>\n", l.bar_x, l.bar_y,
                l.bar_w, l.bar_h);
  out += buffer;
  for (int k = 0; k <= 4; ++k) {
    const int y = l.bar_y + (l.bar_h - 1) * k / 4;
    std::snprintf(buffer, sizeof buffer,
                  "<text x=\"%d\" y=\"%d\" font-family=\"sans-serif\" font-size=\"14\" dominant-baseline=\"middle\">%s</text>\n",
                  l.bar_x + l.bar_w + 8, y, mm_label(l.range * (1.0 - k / 2.0)).c_str());
    out += buffer;
  }
  out += "</svg>\n";
  return out;
}

}  // namespace dg::host
