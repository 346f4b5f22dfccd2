// digitizer-hil: the hardware-in-the-loop rig. A Linux board (any with GPIO through libgpiod)
// wired to a controller's driver and gauge pins plays the table and the dial gauge: it follows the
// table by counting STEP edges with DIR, and answers each REQ by clocking out, bit by bit on CK and
// DATA, a Digimatic reading of a virtual part at the table's position. It prints each reading it
// sends, so a test can hold the controller's scan against it. Wiring: docs/hardware.md.
#include <poll.h>
#include <sys/prctl.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "hw/gpio/gpio_line.h"
#include "hw/hil/real_time_gauge.h"
#include "hw/hil/step_follower.h"
#include "hw/sim/parts.h"

namespace {

volatile std::sig_atomic_t stop_requested = 0;

enum LineIndex { kStepX, kDirX, kStepY, kDirY, kReq, kCk, kData, kLineCount };
constexpr const char* kKeys[kLineCount] = {"step_x", "dir_x", "step_y", "dir_y", "req", "ck", "data"};

uint64_t now_ns() {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<uint64_t>(now.tv_sec) * 1000000000ull + static_cast<uint64_t>(now.tv_nsec);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"digitizer-hil: the hardware-in-the-loop rig: follows a controller's STEP/DIR lines and answers its "
                "gauge requests with Digimatic readings of a virtual part",
                "digitizer-hil"};
  std::vector<std::string> pin_specs;
  std::string part_name = "dome";
  dg::sim::Part part;
  dg::sim::GaugeConfig gauge_config;
  double nm_per_step = 2500, clock_us = gauge_config.clock_low_us, answer_us = gauge_config.request_to_clock_us;
  double noise_um = 0;
  std::string start = "0,0";
  long readings_wanted = -1;
  app.add_option("--pin", pin_specs,
                 "KEY=LINE, KEY one of step_x dir_x step_y dir_y req ck data (all needed); LINE is CHIP:OFFSET or a "
                 "line name, '/active-low' after it inverts it")
      ->required()->allow_extra_args(false);
  app.add_option("--part", part_name, "dome, saddle, canister or flat")->capture_default_str();
  app.add_option("--offset-mm", part.offset_mm, "raise the part by this, mm");
  app.add_option("--nm-per-step", nm_per_step, "the table's travel per step")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--start", start, "the table's position in steps when the rig starts, X,Y")->capture_default_str();
  app.add_option("--clock-us", clock_us, "each CK half period (the Digimatic specification's 200 by default)")
      ->capture_default_str()->check(CLI::Range(1.0, 1e6));
  app.add_option("--answer-us", answer_us, "REQ to the first CK edge")->capture_default_str()->check(CLI::Range(0.0, 1e7));
  app.add_option("--noise-um", noise_um, "Gaussian noise on each reading, um")->check(CLI::NonNegativeNumber);
  app.add_flag("--inch", gauge_config.inch, "readings in inch at 0.0001");
  app.add_option("--readings", readings_wanted, "exit after N readings, once REQ is released (default: run until SIGTERM)")
      ->check(CLI::PositiveNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  gauge_config.clock_low_us = gauge_config.clock_high_us = static_cast<uint32_t>(clock_us);
  gauge_config.request_to_clock_us = static_cast<uint32_t>(answer_us);
  gauge_config.noise_sigma_mm = noise_um / 1000.0;
  long long start_x = 0, start_y = 0;
  char after = 0;
  std::string usage_error;
  if (std::sscanf(start.c_str(), "%lld,%lld%c", &start_x, &start_y, &after) != 2) {
    usage_error = "--start '" + start + "': expected X,Y in steps";
  }
  if (!dg::sim::parse_part(part_name.c_str(), &part.kind)) usage_error = "unknown part '" + part_name + "'";
  dg::gpio::LineSpec specs[kLineCount];
  bool given[kLineCount] = {};
  for (const std::string& pair : pin_specs) {
    const size_t equals = pair.find('=');
    int key = -1;
    for (int k = 0; k < kLineCount && equals != std::string::npos; ++k) {
      if (pair.compare(0, equals, kKeys[k]) == 0 && equals == std::strlen(kKeys[k])) key = k;
    }
    if (key < 0) {
      usage_error = "'" + pair + "': expected KEY=LINE with KEY one of step_x dir_x step_y dir_y req ck data";
    } else if (dg::gpio::parse_line_spec(pair.substr(equals + 1), &specs[key], &usage_error)) {
      given[key] = true;
    }
  }
  if (!usage_error.empty()) {
    std::fprintf(stderr, "digitizer-hil: %s (see --help)\n", usage_error.c_str());
    return 2;
  }
  for (int k = 0; k < kLineCount; ++k) {
    if (!given[k]) {
      std::fprintf(stderr, "digitizer-hil: no line given for %s (--pin %s=LINE)\n", kKeys[k], kKeys[k]);
      return 2;
    }
  }

  dg::gpio::Line lines[kLineCount];
  std::string error;
  using dg::gpio::Bias;
  using dg::gpio::Direction;
  const Direction directions[kLineCount] = {Direction::kRisingEdges, Direction::kBothEdges, Direction::kRisingEdges,
                                            Direction::kBothEdges,   Direction::kBothEdges, Direction::kOutput,
                                            Direction::kOutput};
  for (int k = 0; k < kLineCount; ++k) {
    // CK idles high, as a gauge's does.
    if (!lines[k].request(specs[k], "digitizer-hil", directions[k], Bias::kAsIs, k == kCk, &error)) {
      std::fprintf(stderr, "digitizer-hil: %s\n", error.c_str());
      return 1;
    }
  }
  std::signal(SIGTERM, [](int) { stop_requested = 1; });
  std::signal(SIGINT, [](int) { stop_requested = 1; });
  prctl(PR_SET_TIMERSLACK, 1UL);

  dg::hil::StepFollower table(start_x, start_y, lines[kDirX].get(), lines[kDirY].get());
  dg::hil::RealTimeGauge gauge(gauge_config, now_ns());
  bool request = lines[kReq].get();
  long readings = 0;
  uint32_t frames_seen = 0;
  std::printf("digitizer-hil: following the table from (%lld, %lld) steps; %s part\n", start_x, start_y,
              dg::sim::part_name(part.kind));
  std::fflush(stdout);
  std::vector<dg::hil::Edge> edges;
  const int edge_lines[] = {kStepX, kDirX, kStepY, kDirY, kReq};
  while (!stop_requested) {
    // Done once the last frame is out and the reader has let REQ go: leaving earlier would release
    // CK while the reader may not yet have seen its last rise.
    if (readings_wanted > 0 && readings >= readings_wanted && gauge.due_ns() == UINT64_MAX && !request) break;
    pollfd fds[5];
    for (int n = 0; n < 5; ++n) fds[n] = {lines[edge_lines[n]].event_fd(), POLLIN, 0};
    const uint64_t due = gauge.due_ns();
    const uint64_t now = now_ns();
    timespec timeout{};
    if (due != UINT64_MAX) {
      const uint64_t wait_ns = due > now ? due - now : 0;
      timeout.tv_sec = static_cast<time_t>(wait_ns / 1000000000ull);
      timeout.tv_nsec = static_cast<long>(wait_ns % 1000000000ull);
    }
    const int ready = ppoll(fds, 5, due == UINT64_MAX ? nullptr : &timeout, nullptr);
    if (ready > 0) {
      bool request_changed = false;
      for (int n = 0; n < 5; ++n) {
        if (!(fds[n].revents & POLLIN)) continue;
        const int k = edge_lines[n];
        dg::gpio::Line::EdgeEvent queued[16];
        const int got = lines[k].read_edges(queued, 16);
        for (int e = 0; e < got; ++e) {
          if (k == kReq) {
            request = queued[e].rising;
            request_changed = true;
          } else {
            const int axis = (k == kStepX || k == kDirX) ? 0 : 1;
            const auto line = (k == kStepX || k == kStepY) ? dg::hil::AxisLine::kStep : dg::hil::AxisLine::kDir;
            edges.push_back({queued[e].timestamp_ns, axis, line, queued[e].rising});
          }
        }
      }
      // Each line's edges are queued by its own interrupt thread, so a DIR edge that came before
      // a STEP edge may not be queued yet: until DIR's queued edges end at the level the line has
      // now, wait for the rest (bounded) before counting steps.
      for (int axis = 0; axis < 2; ++axis) {
        dg::gpio::Line& dir = lines[axis == 0 ? kDirX : kDirY];
        for (int tries = 0; tries < 20 && table.dir_after(edges, axis) != dir.get(); ++tries) {
          pollfd fd{dir.event_fd(), POLLIN, 0};
          if (poll(&fd, 1, 1) <= 0) continue;
          dg::gpio::Line::EdgeEvent queued[16];
          const int got = dir.read_edges(queued, 16);
          for (int e = 0; e < got; ++e) edges.push_back({queued[e].timestamp_ns, axis, dg::hil::AxisLine::kDir, queued[e].rising});
        }
      }
      // Steps first: the reading belongs to where the table is when REQ comes.
      table.apply(edges);
      if (request_changed) {
        const double x_mm = static_cast<double>(table.x_steps()) * nm_per_step * 1e-6;
        const double y_mm = static_cast<double>(table.y_steps()) * nm_per_step * 1e-6;
        gauge.set_request(request, now_ns(), part.height_mm(x_mm, y_mm));
      }
    }
    // The CK change now due (one per pass), DATA first so it is settled before CK rises.
    if (gauge.advance(now_ns())) {
      lines[kData].set(gauge.data());
      lines[kCk].set(gauge.clock());
    }
    if (gauge.model().frames_sent() != frames_seen) {
      frames_seen = gauge.model().frames_sent();
      ++readings;
      const dg::DigimaticReading& reading = gauge.model().reading();
      std::printf("reading %ld: x_steps=%lld y_steps=%lld value=%d decimals=%u unit=%s\n", readings,
                  static_cast<long long>(table.x_steps()), static_cast<long long>(table.y_steps()), reading.value,
                  reading.decimals, reading.unit == dg::GaugeUnit::kInch ? "inch" : "mm");
      std::fflush(stdout);
    }
  }
  std::printf("digitizer-hil: %ld readings, %llu steps followed, table at (%lld, %lld) steps\n", readings,
              static_cast<unsigned long long>(table.steps()), static_cast<long long>(table.x_steps()),
              static_cast<long long>(table.y_steps()));
  return 0;
}
