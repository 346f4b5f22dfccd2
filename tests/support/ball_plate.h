// The simulated ball plate's certificate, as docs/ball-plate-sim.csv has it: in memory, and as a
// file for the commands that read one.
#pragma once
#include <cstdio>
#include <string>
#include <vector>

#include "host/geometry/trimmed_face.h"
#include "hw/sim/parts.h"

namespace dg::test {

inline std::vector<host::Point2> ball_plate_certificate() {
  std::vector<host::Point2> out;
  for (int ball = 0; ball < sim::kBallPlateBalls; ++ball) {
    host::Point2 p;
    sim::ball_plate_centre(ball, &p.x, &p.y);
    out.push_back(p);
  }
  return out;
}

inline std::string write_ball_plate_certificate(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) return "";
  std::fprintf(f, "x_mm,y_mm\n");
  for (const host::Point2& p : ball_plate_certificate()) std::fprintf(f, "%g,%g\n", p.x, p.y);
  std::fclose(f);
  return path;
}

}  // namespace dg::test
