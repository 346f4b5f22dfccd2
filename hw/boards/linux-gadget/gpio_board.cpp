// Step timing on Linux: each tick is due at the previous tick's due time plus the handler's
// interval (chained, as on the STM32 board, so a few microseconds of wake-up latency do not
// accumulate into the motion). A tick more than 50 us late starts the schedule again from now
// instead: catching up would send the missed steps in a burst faster than the motors can follow
// (a stalled stepper loses them), whereas a stretched interval only slows the move. ppoll sleeps
// to the next due time with a 1 us timer slack; the STEP pulse is held 2 us by spinning (drivers
// such as the DRV8825 need 1.9 us).
#include "hw/boards/linux-gadget/gpio_board.h"

#include "firmware/hal/step_schedule.h"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>
#include <sys/prctl.h>

#include <cstdio>
#include <cstring>
#include <ctime>

namespace dg::gadget {

namespace {

constexpr uint64_t kStepPulseNs = 2000;
// A process may wake this late and still chain its steps; later, the move is stretched instead.
constexpr uint64_t kLateStepNs = 50000;

int index(hal::Pin pin) { return static_cast<int>(pin); }

bool is_output(int pin) {
  const auto p = static_cast<hal::Pin>(pin);
  return p == hal::Pin::kStepX || p == hal::Pin::kDirX || p == hal::Pin::kStepY || p == hal::Pin::kDirY ||
         p == hal::Pin::kGaugeReq;
}

bool is_step(int pin) { return pin == index(hal::Pin::kStepX) || pin == index(hal::Pin::kStepY); }

// Switches are normally closed to ground: the pull-up makes an open switch (or a cut wire) read
// asserted. The gauge's CK and DATA idle high through the level shifter.
gpio::Bias input_bias(int pin) {
  return is_output(pin) ? gpio::Bias::kAsIs : gpio::Bias::kPullUp;
}

}  // namespace

GpioBoard::GpioBoard(FunctionFsLink& link) : link_(link) {
  prctl(PR_SET_TIMERSLACK, 1UL);
  epoch_ns_ = now_ns();
}

uint64_t GpioBoard::now_ns() const {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<uint64_t>(now.tv_sec) * 1000000000ull + static_cast<uint64_t>(now.tv_nsec) - epoch_ns_;
}

bool GpioBoard::open(const PinMap& map, std::string* error) {
  for (int pin = 0; pin < kPinCount; ++pin) {
    if (!map.wired[pin]) continue;
    const auto p = static_cast<hal::Pin>(pin);
    // CK, the touch probe and the e-stop raise "interrupts" (the e-stop's cuts the drivers between
    // steps, and while the table stands still); DATA's edges are kept to know its level at each CK
    // edge; every other input is read when wanted.
    const gpio::Direction direction = is_output(pin) ? gpio::Direction::kOutput
                                      : (p == hal::Pin::kGaugeClock || p == hal::Pin::kTouchProbe || p == hal::Pin::kEstop)
                                          ? gpio::Direction::kRisingEdges
                                      : p == hal::Pin::kGaugeData ? gpio::Direction::kBothEdges
                                                                  : gpio::Direction::kInput;
    if (!lines_[pin].request(map.pins[pin], "digitizer", direction, input_bias(pin), false, error)) return false;
  }
  data_ = ClockedData(lines_[index(hal::Pin::kGaugeData)].get());
  if (map.enable_wired &&
      !enable_.request(map.driver_enable, "digitizer", gpio::Direction::kOutput, gpio::Bias::kAsIs, true, error)) {
    return false;
  }
  return true;
}

void GpioBoard::enable_drivers(bool on) {
  // The line's polarity (EN is active low) is in its spec; unwired, there is nothing to switch.
  if (enable_.requested()) enable_.set(on);
}

void GpioBoard::write_pin(hal::Pin pin, bool level) {
  const int i = index(pin);
  if (is_step(i)) {
    if (level) {
      step_high_ns_[i] = now_ns();
    } else {
      while (now_ns() - step_high_ns_[i] < kStepPulseNs) {
      }
    }
  }
  level_[i] = level;
  lines_[i].set(level);
}

bool GpioBoard::read_pin(hal::Pin pin) {
  const int i = index(pin);
  if (is_output(i)) return level_[i];
  if (pin == hal::Pin::kGaugeData && in_clock_edge_) return data_at_clock_;
  return lines_[i].requested() && lines_[i].get();
}

void GpioBoard::on_rising_edge(hal::Pin pin, hal::EdgeHandler handler, void* context) {
  edge_handler_[index(pin)] = handler;
  edge_context_[index(pin)] = context;
}

void GpioBoard::start_step_timer(uint32_t delay_ns, hal::TimerHandler handler, void* context) {
  timer_handler_ = handler;
  timer_context_ = context;
  timer_due_ns_ = now_ns() + delay_ns;
}

void GpioBoard::stop_step_timer() { timer_due_ns_ = kNever; }

bool GpioBoard::run_step_timer() {
  uint64_t now = now_ns();
  while (timer_due_ns_ != kNever && timer_due_ns_ <= now) {
    if (hal::step_late<uint64_t>(timer_due_ns_, now, kLateStepNs)) ++late_steps_;
    ++timer_ticks_;
    const uint32_t next_ns = timer_handler_(timer_context_);
    if (next_ns == 0) {
      timer_due_ns_ = kNever;
      return true;
    }
    timer_due_ns_ = hal::next_step_due<uint64_t>(timer_due_ns_, now, next_ns, kLateStepNs);
    now = now_ns();
  }
  return false;
}

void GpioBoard::take_data_edges() {
  gpio::Line& data = lines_[index(hal::Pin::kGaugeData)];
  for (;;) {
    pollfd fd{data.event_fd(), POLLIN, 0};
    if (poll(&fd, 1, 0) <= 0) return;
    gpio::Line::EdgeEvent events[16];
    const int got = data.read_edges(events, 16);
    if (got <= 0) return;
    for (int i = 0; i < got; ++i) data_.add(events[i].timestamp_ns, events[i].rising);
  }
}

void GpioBoard::settle_data() {
  gpio::Line& data = lines_[index(hal::Pin::kGaugeData)];
  if (!data.requested()) return;
  // The kernel queues each line's edges from its own interrupt thread, so a DATA edge that came
  // before a CK edge may not be queued yet when the CK edge is. Until the queued edges end at
  // the level DATA has now, one is still on its way: wait for it (bounded).
  for (int tries = 0; tries < 20; ++tries) {
    take_data_edges();
    if (data_.queued_level() == data.get()) return;
    pollfd fd{data.event_fd(), POLLIN, 0};
    poll(&fd, 1, 1);
  }
  data_.mark_doubtful();
}

bool GpioBoard::dispatch_edges(int pin) {
  gpio::Line::EdgeEvent events[16];
  const int got = lines_[pin].read_edges(events, 16);
  const bool clock = pin == index(hal::Pin::kGaugeClock);
  if (clock && got > 0) settle_data();
  bool any = false;
  for (int i = 0; i < got; ++i) {
    if (!events[i].rising || edge_handler_[pin] == nullptr) continue;
    if (clock) {
      data_at_clock_ = data_.level_at(events[i].timestamp_ns);
      if (data_.take_doubtful()) {
        // This bit, or one before it, may be wrong: without this edge the reader times the frame
        // out and reads it again.
        ++dropped_clock_edges_;
        continue;
      }
    }
    in_clock_edge_ = clock;
    edge_handler_[pin](edge_context_[pin]);
    in_clock_edge_ = false;
    any = true;
  }
  return any;
}

bool GpioBoard::wait(uint64_t deadline_us) {
  const uint64_t deadline_ns = deadline_us == UINT64_MAX ? kNever : deadline_us * 1000;
  // The e-stop first: its handler cuts the drivers before a gauge bit is decoded.
  const int edge_pins[] = {index(hal::Pin::kEstop), index(hal::Pin::kGaugeClock), index(hal::Pin::kTouchProbe)};
  for (;;) {
    if (link_.closed()) return false;
    if (run_step_timer()) return true;  // a move ended: the firmware moves on
    const uint64_t now = now_ns();
    if (deadline_ns != kNever && deadline_ns <= now) return true;
    const uint64_t next = timer_due_ns_ < deadline_ns ? timer_due_ns_ : deadline_ns;
    // The link's wake-up first, then each requested edge line; polled_pin[n] is fds[n]'s pin.
    constexpr size_t kFds = 1 + sizeof(edge_pins) / sizeof(edge_pins[0]);
    pollfd fds[kFds];
    int count = 0;
    fds[count++] = {link_.wake_fd(), POLLIN, 0};
    int polled_pin[kFds] = {};
    for (int pin : edge_pins) {
      if (lines_[pin].requested()) {
        polled_pin[count] = pin;
        fds[count++] = {lines_[pin].event_fd(), POLLIN, 0};
      }
    }
    timespec timeout{};
    if (next != kNever) {
      const uint64_t wait_ns = next - now;
      timeout.tv_sec = static_cast<time_t>(wait_ns / 1000000000ull);
      timeout.tv_nsec = static_cast<long>(wait_ns % 1000000000ull);
    }
    const int ready = ppoll(fds, static_cast<nfds_t>(count), next == kNever ? nullptr : &timeout, nullptr);
    if (ready <= 0) continue;  // a timer is due (or a signal): loop round
    bool woke = false;
    if (fds[0].revents & POLLIN) {
      link_.drain_wake();
      woke = true;
    }
    for (int i = 1; i < count; ++i) {
      if ((fds[i].revents & POLLIN) && dispatch_edges(polled_pin[i])) woke = true;
    }
    if (woke) return true;
  }
}

bool GpioBoard::store_settings(const uint8_t* data, size_t size) {
  if (settings_path_.empty()) return false;
  const std::string temporary = settings_path_ + ".new";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  const bool written = ::write(fd, data, size) == static_cast<ssize_t>(size) && ::fsync(fd) == 0;
  if (::close(fd) != 0 || !written || std::rename(temporary.c_str(), settings_path_.c_str()) != 0) {
    ::unlink(temporary.c_str());
    return false;
  }
  return true;
}

size_t GpioBoard::load_settings(uint8_t* data, size_t capacity) {
  if (settings_path_.empty()) return 0;
  const int fd = ::open(settings_path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 0;
  const ssize_t got = ::read(fd, data, capacity);
  ::close(fd);
  return got > 0 ? static_cast<size_t>(got) : 0;
}

}  // namespace dg::gadget
