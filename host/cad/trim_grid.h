// A raster over a face's (u, v) domain that answers "inside the trims" at once for the cells far
// from every trim curve, so the exact classifier is asked only near the face's edges.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace dg::host {

class TrimGrid {
 public:
  using Segment = std::array<double, 4>;  // u0, v0, u1, v1 of a piece of the trims' polygon

  TrimGrid() = default;
  // `boundary`: the face's trims as polygons in (u, v) whose true curves lie within `sagitta` of
  // them; `inside(u, v)`: the exact classifier, asked once per cell centre. A cell is marked inside
  // when its centre is and no boundary segment comes within the cell's half-diagonal plus twice
  // the sagitta.
  TrimGrid(const std::vector<Segment>& boundary, double sagitta, const std::function<bool(double, double)>& inside,
           int cells_per_side = 64);

  // True only where the whole cell is inside the trims; false means "ask the classifier".
  bool surely_inside(double u, double v) const;

 private:
  double u0_ = 0, v0_ = 0, du_ = 0, dv_ = 0;
  int n_ = 0;
  std::vector<uint8_t> inside_;
};

}  // namespace dg::host
