// The host link of the Linux-gadget board: the vendor interface's two bulk endpoints through a
// mounted FunctionFS instance. FunctionFS I/O blocks, so one thread reads endpoint 0's events, one
// reads bulk OUT and one writes bulk IN; the firmware's thread sees byte queues and an eventfd.
// A pulled cable (the UDC unbound, the host gone) is not a close: bytes wait until it is back.
#pragma once
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <thread>

#include "firmware/hal/link_port.h"

namespace dg::gadget {

class FunctionFsLink final : public hal::LinkPort {
 public:
  // `mount_dir`: where the function's FunctionFS instance is mounted (holds ep0).
  explicit FunctionFsLink(std::string mount_dir);
  ~FunctionFsLink() override;
  FunctionFsLink(const FunctionFsLink&) = delete;
  FunctionFsLink& operator=(const FunctionFsLink&) = delete;

  // Writes the descriptors and strings, opens the bulk endpoints and starts the I/O threads.
  // false with the reason when FunctionFS refuses.
  bool start(std::string* error);

  size_t write(const uint8_t* data, size_t size) override;
  size_t read(uint8_t* data, size_t capacity) override;
  bool wait_readable(int timeout_ms = -1) override;
  bool closed() const override { return stop_.load(); }

  // Readable when bytes arrived or the link is closing; a board polls it beside its other events.
  int wake_fd() const { return wake_fd_; }
  void drain_wake();
  // Closes the link from a signal handler: the firmware's wait returns false.
  void request_stop();
  // The host has configured the interface (FunctionFS ENABLE) and not since dropped it.
  bool connected() const { return enabled_.load(); }
  // The host suspended the bus (FunctionFS SUSPEND) and has not resumed or re-enabled it since.
  bool suspended() const { return suspended_.load(); }
  // How many times the host has dropped the link (DISABLE, UNBIND or SUSPEND), for the log.
  uint32_t drops() const { return drops_.load(); }

 private:
  void event_loop();
  void read_loop();
  void write_loop();
  void set_enabled(bool enabled);
  void wake();

  std::string dir_;
  int ep0_ = -1, out_ = -1, in_ = -1;
  int wake_fd_ = -1;
  std::atomic<bool> stop_{false};
  std::atomic<bool> enabled_{false};
  std::atomic<bool> suspended_{false};
  std::atomic<uint32_t> drops_{0};
  std::atomic<int> running_{0};  // I/O threads not yet finished
  std::mutex mutex_;
  std::condition_variable tx_ready_;
  std::deque<uint8_t> rx_, tx_;
  std::thread events_, reader_, writer_;
};

}  // namespace dg::gadget
