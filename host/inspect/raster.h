// A small RGB raster for report pictures: rectangles, numeric labels, and PNG through libpng.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace dg::host {

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
};

class Raster {
 public:
  Raster(int width, int height, Rgb background);
  int width() const { return width_; }
  int height() const { return height_; }
  // Fills [x0, x1) x [y0, y1), clipped to the picture.
  void fill(int x0, int y0, int x1, int y1, Rgb colour);
  // Text in a 5 x 7 pixel font scaled by `scale`: digits, '.', '-', '+', 'm', '<', '>', ' ' (what
  // axis and colour-bar labels in millimetres need). Other characters are left blank.
  void text(int x, int y, const std::string& s, Rgb colour, int scale = 2);
  // The picture as a PNG file's bytes (8-bit RGB). Throws std::runtime_error if libpng fails.
  std::string png() const;

 private:
  int width_, height_;
  std::vector<Rgb> pixels_;
};

}  // namespace dg::host
