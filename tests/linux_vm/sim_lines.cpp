// system-lines: the far end of gpio-sim lines, for the system tests. gpio-sim offers no wire
// between two consumers; the far end of a line is its sysfs attributes (`pull` drives an input,
// `value` shows an output), and this program works them at the pin level:
//   system-lines gauge DIR REQ CK DATA VALUE_MM[,VALUE_MM...]  plays a Digimatic gauge to a
//       controller: waits for REQ, clocks out the next value on CK/DATA (1 ms half periods)
//   system-lines read DIR STEP_X DIR_X STEP_Y DIR_Y REQ CK DATA DX DY  plays a controller to a
//       gauge (the HIL rig): DX, DY step pulses, then REQ, and decodes what comes back
// DIR is the chip's sysfs directory (/sys/devices/platform/gpio-sim.N/gpiochipM); lines are offsets.
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "firmware/core/digimatic.h"
#include "hw/hil/real_time_gauge.h"

namespace {

uint64_t now_ns() {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<uint64_t>(now.tv_sec) * 1000000000ull + static_cast<uint64_t>(now.tv_nsec);
}

void sleep_until(uint64_t when_ns) {
  timespec at{static_cast<time_t>(when_ns / 1000000000ull), static_cast<long>(when_ns % 1000000000ull)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, nullptr) != 0) {
  }
}

class SimLine {
 public:
  SimLine(const std::string& chip_dir, int offset) {
    const std::string base = chip_dir + "/sim_gpio" + std::to_string(offset);
    value_ = open((base + "/value").c_str(), O_RDONLY | O_CLOEXEC);
    pull_ = open((base + "/pull").c_str(), O_WRONLY | O_CLOEXEC);
    if (value_ < 0 || pull_ < 0) {
      std::fprintf(stderr, "system-lines: %s: %s\n", base.c_str(), std::strerror(errno));
      std::exit(1);
    }
  }
  bool value() const {
    char text[4] = {};
    if (pread(value_, text, sizeof text - 1, 0) <= 0) {
      std::fprintf(stderr, "system-lines: cannot read a line value: %s\n", std::strerror(errno));
      std::exit(1);
    }
    return text[0] == '1';
  }
  void drive(bool high) const {
    const char* text = high ? "pull-up" : "pull-down";
    if (pwrite(pull_, text, std::strlen(text), 0) < 0) {
      std::fprintf(stderr, "system-lines: cannot set a pull: %s\n", std::strerror(errno));
      std::exit(1);
    }
  }

 private:
  int value_ = -1, pull_ = -1;
};

int play_gauge(const std::string& dir, int req_line, int ck_line, int data_line, const char* values_text) {
  std::vector<double> values;
  for (const char* at = values_text; *at != '\0';) {
    char* end = nullptr;
    values.push_back(std::strtod(at, &end));
    if (end == at) return 2;
    at = *end == ',' ? end + 1 : end;
  }
  const SimLine req(dir, req_line), ck(dir, ck_line), data(dir, data_line);
  ck.drive(true);
  data.drive(true);
  dg::sim::GaugeConfig config;
  config.clock_low_us = config.clock_high_us = 1000;
  config.request_to_clock_us = 2000;
  dg::hil::RealTimeGauge gauge(config, now_ns());
  size_t next = 0;
  bool request = false;
  for (;;) {
    const bool asserted = req.value();
    if (asserted != request) {
      request = asserted;
      gauge.set_request(request, now_ns(), values[next % values.size()]);
      if (request && gauge.due_ns() != UINT64_MAX) {
        std::printf("gauge: sending %.3f\n", values[next % values.size()]);
        std::fflush(stdout);
        ++next;
      }
    }
    while (gauge.due_ns() != UINT64_MAX) {
      sleep_until(gauge.due_ns());
      gauge.advance(now_ns());
      data.drive(gauge.data());
      ck.drive(gauge.clock());
    }
    usleep(200);
  }
}

int read_gauge(const std::string& dir, const int lines[7], long dx, long dy) {
  const SimLine step_x(dir, lines[0]), dir_x(dir, lines[1]), step_y(dir, lines[2]), dir_y(dir, lines[3]);
  const SimLine req(dir, lines[4]), ck(dir, lines[5]), data(dir, lines[6]);
  dir_x.drive(dx >= 0);
  dir_y.drive(dy >= 0);
  usleep(1000);
  // Paced: gpiolib reports an edge from a threaded interrupt handler, and two edges that come
  // before the thread runs are reported as one. Under software emulation the thread can be
  // milliseconds late.
  for (long i = 0; i < labs(dx); ++i) {
    step_x.drive(true);
    usleep(2000);
    step_x.drive(false);
    usleep(4000);
  }
  for (long i = 0; i < labs(dy); ++i) {
    step_y.drive(true);
    usleep(2000);
    step_y.drive(false);
    usleep(4000);
  }
  usleep(1000);
  // Sample DATA at each CK rise, as a Digimatic receiver does. A receiver that misses a rise asks
  // again, as a real one must: under software emulation this polling reader or the rig can stall
  // for longer than a CK phase.
  dg::DigimaticBits bits;
  int count = 0;
  for (int attempt = 1; attempt <= 3 && count < dg::kDigimaticBits; ++attempt) {
    if (attempt > 1) {
      std::printf("read: only %d of %d bits came; asking again\n", count, dg::kDigimaticBits);
      // The rig finishes the frame it began: wait until CK has been still for half a second.
      bool level = ck.value();
      uint64_t still_since = now_ns();
      while (now_ns() - still_since < 500000000ull) {
        if (ck.value() != level) {
          level = !level;
          still_since = now_ns();
        }
        usleep(1000);
      }
    }
    bits = dg::DigimaticBits{};
    count = 0;
    req.drive(true);
    bool clock = ck.value();
    const uint64_t give_up = now_ns() + 10000000000ull;
    while (count < dg::kDigimaticBits && now_ns() < give_up) {
      const bool level = ck.value();
      if (level && !clock) bits.set_bit(count++, data.value());
      clock = level;
    }
    req.drive(false);
  }
  if (count < dg::kDigimaticBits) {
    std::printf("read: only %d of %d bits came, three times\n", count, dg::kDigimaticBits);
    return 1;
  }
  dg::DigimaticReading reading;
  if (dg::digimatic_decode(bits, &reading) != dg::Status::kOk) {
    std::printf("read: the frame does not decode\n");
    return 1;
  }
  std::printf("read: value=%d decimals=%u unit=%s\n", reading.value, reading.decimals,
              reading.unit == dg::GaugeUnit::kInch ? "inch" : "mm");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 7 && std::strcmp(argv[1], "gauge") == 0) {
    return play_gauge(argv[2], std::atoi(argv[3]), std::atoi(argv[4]), std::atoi(argv[5]), argv[6]);
  }
  if (argc == 12 && std::strcmp(argv[1], "read") == 0) {
    int lines[7];
    for (int i = 0; i < 7; ++i) lines[i] = std::atoi(argv[3 + i]);
    return read_gauge(argv[2], lines, std::atol(argv[10]), std::atol(argv[11]));
  }
  std::fprintf(stderr, "usage: system-lines gauge DIR REQ CK DATA VALUES | read DIR SX DX SY DY REQ CK DATA DX DY\n");
  return 2;
}
