// A point sink for firmware scan tests and benches: keeps every point, never full.
#pragma once
#include <vector>

#include "firmware/core/scan_engine.h"

namespace dg::test {

struct CollectPoints final : dg::PointSink {
  bool accept(const dg::PointSample& p) override {
    points.push_back(p);
    return true;
  }
  std::vector<dg::PointSample> points;
};

}  // namespace dg::test
