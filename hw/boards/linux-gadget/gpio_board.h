// The Linux-gadget board's pins and time: the firmware HAL on libgpiod lines, CLOCK_MONOTONIC and
// the FunctionFS link. The firmware runs on one thread; "interrupts" (the step timer, CK and
// touch edges) are dispatched inside wait(), as the firmware's main loop would see them.
#pragma once
#include <cstdint>
#include <string>

#include "firmware/hal/board.h"
#include "hw/boards/linux-gadget/clocked_data.h"
#include "hw/boards/linux-gadget/functionfs_link.h"
#include "hw/boards/linux-gadget/pin_map.h"
#include "hw/gpio/gpio_line.h"

namespace dg::gadget {

class GpioBoard final : public hal::Board {
 public:
  explicit GpioBoard(FunctionFsLink& link);
  // Requests every wired line; false with the first line that could not be had.
  bool open(const PinMap& map, std::string* error);

  void write_pin(hal::Pin pin, bool level) override;
  bool read_pin(hal::Pin pin) override;
  void enable_drivers(bool on) override;
  void on_rising_edge(hal::Pin pin, hal::EdgeHandler handler, void* context) override;
  void start_step_timer(uint32_t delay_ns, hal::TimerHandler handler, void* context) override;
  void stop_step_timer() override;
  uint64_t now_us() override { return now_ns() / 1000; }
  size_t link_write(const uint8_t* data, size_t size) override { return link_.write(data, size); }
  size_t link_read(uint8_t* data, size_t capacity) override { return link_.read(data, capacity); }
  bool link_suspended() override { return link_.suspended(); }
  bool wait(uint64_t deadline_us) override;
  // The settings (the calibration's summary) in a file, where one is named: written to a file
  // beside it, synced and renamed over it, so a power cut leaves the old or the new one whole.
  void keep_settings_in(const std::string& path) { settings_path_ = path; }
  bool store_settings(const uint8_t* data, size_t size) override;
  size_t load_settings(uint8_t* data, size_t capacity) override;

  // Step timer ticks, and those that fired later than 50 us past due (a loaded Linux is not an MCU).
  uint64_t timer_ticks() const { return timer_ticks_; }
  uint64_t late_steps() const { return late_steps_; }
  // CK edges left out because DATA's record at them was doubtful (each costs a gauge reading).
  uint64_t dropped_clock_edges() const { return dropped_clock_edges_; }

 private:
  static constexpr uint64_t kNever = UINT64_MAX;
  uint64_t now_ns() const;
  // Runs the step handler for every tick now due; true when a move ended.
  bool run_step_timer();
  bool dispatch_edges(int pin);
  // Moves DATA's queued edges into data_; settle_data() also waits for any still on its way.
  void take_data_edges();
  void settle_data();

  FunctionFsLink& link_;
  gpio::Line lines_[kPinCount];
  gpio::Line enable_;
  bool level_[kPinCount] = {};
  uint64_t step_high_ns_[kPinCount] = {};
  hal::EdgeHandler edge_handler_[kPinCount] = {};
  void* edge_context_[kPinCount] = {};
  hal::TimerHandler timer_handler_ = nullptr;
  void* timer_context_ = nullptr;
  uint64_t timer_due_ns_ = kNever;
  uint64_t late_steps_ = 0;
  uint64_t timer_ticks_ = 0;
  // The gauge's DATA as it was at the CK edge being dispatched (a process sees edges late).
  ClockedData data_;
  bool data_at_clock_ = false;
  uint64_t dropped_clock_edges_ = 0;
  bool in_clock_edge_ = false;
  uint64_t epoch_ns_ = 0;
  std::string settings_path_;
};

}  // namespace dg::gadget
