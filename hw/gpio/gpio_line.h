// One GPIO line through libgpiod (the character device): named in a pin map as "CHIP:OFFSET" or by
// its line name, optionally "/active-low", and requested as an output, an input or an edge source.
// Shared by the Linux-gadget board and the hardware-in-the-loop rig.
#pragma once
#include <cstdint>
#include <string>

struct gpiod_chip;
struct gpiod_line;

namespace dg::gpio {

struct LineSpec {
  std::string chip;   // "gpiochip0", a path or a label; empty: find the line by name on any chip
  unsigned offset = 0;
  std::string name;   // the line's name when chip is empty
  bool active_low = false;
};

// Parses "gpiochip0:17", "GPIO17", "/dev/gpiochip1:3/active-low" or "GPIO5/active-low".
// false, with the reason, when the text is none of these.
bool parse_line_spec(const std::string& text, LineSpec* spec, std::string* error);
std::string describe(const LineSpec& spec);

enum class Direction : uint8_t { kOutput, kInput, kRisingEdges, kBothEdges };
enum class Bias : uint8_t { kAsIs, kPullUp, kPullDown };

// A requested line; released (an output first driven inactive) when destroyed.
class Line {
 public:
  Line() = default;
  ~Line();
  Line(const Line&) = delete;
  Line& operator=(const Line&) = delete;

  // false with the reason (no such chip or line, busy) when the line cannot be had.
  bool request(const LineSpec& spec, const char* consumer, Direction direction, Bias bias, bool initial,
               std::string* error);
  bool requested() const { return line_ != nullptr; }

  // Logical levels: true = active (high, or low for an active-low line).
  bool set(bool level);
  bool get();
  // The file descriptor that polls readable when an edge is queued (edge lines only).
  int event_fd() const;
  // Reads up to `capacity` (at most 16, the kernel's queue) queued edges at once; returns how many.
  struct EdgeEvent {
    uint64_t timestamp_ns;
    bool rising;
  };
  int read_edges(EdgeEvent* events, int capacity);

 private:
  gpiod_chip* chip_ = nullptr;
  gpiod_line* line_ = nullptr;
  Direction direction_ = Direction::kInput;
};

}  // namespace dg::gpio
