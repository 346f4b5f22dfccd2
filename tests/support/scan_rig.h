// The scan engine on the simulated board with a Digimatic reader, run to its end: for the
// firmware's scan tests.
#pragma once
#include <CppUTest/TestHarness.h>

#include <vector>

#include "firmware/core/digimatic_reader.h"
#include "firmware/core/scan_engine.h"
#include "hw/sim/sim_board.h"
#include "tests/support/collect_points.h"

namespace dg::test {

struct ScanRig {
  explicit ScanRig(dg::sim::SimConfig c)
      : board(c, nullptr), motion(board, dg::MotionConfig{}), gauge(board, timing()), scan(board, motion, gauge, dg::ScanLimits{}) {
    gauge.attach();
  }
  static dg::DigimaticTiming timing() {
    dg::DigimaticTiming t;
    t.first_clock_timeout_us = 200000;
    return t;
  }
  // Runs the request to its end; fails the test when it is refused or does not finish.
  std::vector<dg::PointSample> run(const digitizer_ScanRequest& r) {
    const char* reason = "";
    CHECK(scan.start(r, 1, 10000, &reason) == digitizer_FaultCode_FAULT_NONE);
    CollectPoints sink;
    for (int guard = 0; guard < 10000000 && !scan.finished(); ++guard) {
      scan.poll(sink);
      if (!scan.finished() && !board.wait(scan.deadline_us())) break;
    }
    CHECK(scan.finished());
    return sink.points;
  }
  dg::sim::SimBoard board;
  dg::StepGenerator motion;
  dg::DigimaticReader gauge;
  dg::ScanEngine scan;
};

}  // namespace dg::test
