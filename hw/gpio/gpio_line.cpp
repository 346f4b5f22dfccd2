// libgpiod v1 calls behind Line (Debian bookworm ships libgpiod 1.6).
#include "hw/gpio/gpio_line.h"

#include <gpiod.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace dg::gpio {

namespace {
constexpr char kActiveLow[] = "/active-low";
}

bool parse_line_spec(const std::string& text, LineSpec* spec, std::string* error) {
  LineSpec out;
  std::string body = text;
  const size_t suffix = sizeof(kActiveLow) - 1;
  if (body.size() > suffix && body.compare(body.size() - suffix, suffix, kActiveLow) == 0) {
    out.active_low = true;
    body.resize(body.size() - suffix);
  }
  if (body.empty()) {
    *error = "empty line name";
    return false;
  }
  const size_t colon = body.rfind(':');
  if (colon == std::string::npos) {
    if (body.find('/') != std::string::npos) {
      *error = "'" + text + "' is not CHIP:OFFSET (for example gpiochip0:17) or a line name";
      return false;
    }
    out.name = body;
  } else {
    const std::string number = body.substr(colon + 1);
    char* end = nullptr;
    errno = 0;
    const unsigned long offset = std::strtoul(number.c_str(), &end, 10);
    if (colon == 0 || number.empty() || *end != '\0' || errno != 0 || offset > 4095) {
      *error = "'" + text + "' is not CHIP:OFFSET (for example gpiochip0:17) or a line name";
      return false;
    }
    out.chip = body.substr(0, colon);
    out.offset = static_cast<unsigned>(offset);
  }
  *spec = out;
  return true;
}

std::string describe(const LineSpec& spec) {
  std::string text = spec.chip.empty() ? spec.name : spec.chip + ":" + std::to_string(spec.offset);
  return spec.active_low ? text + kActiveLow : text;
}

Line::~Line() {
  if (line_ != nullptr) {
    if (direction_ == Direction::kOutput) gpiod_line_set_value(line_, 0);
    gpiod_line_release(line_);
  }
  if (chip_ != nullptr) gpiod_chip_close(chip_);
}

bool Line::request(const LineSpec& spec, const char* consumer, Direction direction, Bias bias, bool initial,
                   std::string* error) {
  if (spec.chip.empty()) {
    line_ = gpiod_line_find(spec.name.c_str());
    if (line_ == nullptr) {
      *error = "no GPIO line is named '" + spec.name + "'";
      return false;
    }
    chip_ = gpiod_line_get_chip(line_);  // gpiod_line_find opened it for us; we close it
  } else {
    chip_ = gpiod_chip_open_lookup(spec.chip.c_str());
    if (chip_ == nullptr) {
      *error = "no GPIO chip '" + spec.chip + "': " + std::strerror(errno);
      return false;
    }
    line_ = gpiod_chip_get_line(chip_, spec.offset);
    if (line_ == nullptr) {
      *error = "GPIO chip '" + spec.chip + "' has no line " + std::to_string(spec.offset);
      return false;
    }
  }
  int flags = spec.active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0;
  if (bias == Bias::kPullUp) flags |= GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP;
  if (bias == Bias::kPullDown) flags |= GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_DOWN;
  int status = -1;
  switch (direction) {
    case Direction::kOutput:
      status = gpiod_line_request_output_flags(line_, consumer, flags, initial ? 1 : 0);
      break;
    case Direction::kInput:
      status = gpiod_line_request_input_flags(line_, consumer, flags);
      break;
    case Direction::kRisingEdges:
      status = gpiod_line_request_rising_edge_events_flags(line_, consumer, flags);
      break;
    case Direction::kBothEdges:
      status = gpiod_line_request_both_edges_events_flags(line_, consumer, flags);
      break;
  }
  if (status != 0) {
    *error = "cannot request GPIO line " + describe(spec) + ": " + std::strerror(errno);
    line_ = nullptr;
    return false;
  }
  direction_ = direction;
  return true;
}

bool Line::set(bool level) { return line_ != nullptr && gpiod_line_set_value(line_, level ? 1 : 0) == 0; }

bool Line::get() { return line_ != nullptr && gpiod_line_get_value(line_) == 1; }

int Line::event_fd() const { return line_ == nullptr ? -1 : gpiod_line_event_get_fd(line_); }

int Line::read_edges(EdgeEvent* events, int capacity) {
  gpiod_line_event raw[16];
  if (line_ == nullptr || capacity <= 0) return 0;
  const int got = gpiod_line_event_read_multiple(line_, raw, capacity < 16 ? static_cast<unsigned>(capacity) : 16u);
  for (int i = 0; i < got; ++i) {
    events[i].timestamp_ns =
        static_cast<uint64_t>(raw[i].ts.tv_sec) * 1000000000ull + static_cast<uint64_t>(raw[i].ts.tv_nsec);
    events[i].rising = raw[i].event_type == GPIOD_LINE_EVENT_RISING_EDGE;
  }
  return got < 0 ? 0 : got;
}

}  // namespace dg::gpio
