// FunctionFS endpoint files: ep0 carries the descriptors and then the function's events; ep1 is
// bulk OUT and ep2 bulk IN, numbered in the order the descriptors declare them. Reads and writes
// on them block until the host has enabled the interface, so a thread that waits through a pulled
// cable simply carries on when it is back. Layouts: linux/usb/functionfs.h.
#include "hw/boards/linux-gadget/functionfs_link.h"

#include <fcntl.h>
#include <linux/usb/ch9.h>
#include <linux/usb/functionfs.h>
#include <poll.h>
#include <pthread.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <vector>

#include "hw/boards/linux-gadget/functionfs_descriptors.h"

namespace dg::gadget {

namespace {

// Bytes queued for the host beyond this are refused: the firmware keeps them and tries again. Small,
// because what waits here while no program on the host reads (retransmissions, mostly) reaches the
// next one as stale bytes it must skip.
constexpr size_t kTxCapacity = 4096;
// One bulk IN write. FunctionFS sends no zero-length packet, so a write that fills whole packets
// would leave the host's transfer waiting for more; the writer trims such a write by one byte.
constexpr size_t kWriteChunk = 4096;
constexpr size_t kPacketDivisor = 64;  // divides both full speed's 64 and high speed's 512

// Interrupts a thread blocked in FunctionFS I/O: the handler does nothing, the call returns EINTR.
void on_wake_signal(int) {}

void install_wake_signal() {
  struct sigaction action {};
  action.sa_handler = on_wake_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;  // no SA_RESTART
  sigaction(SIGUSR2, &action, nullptr);
}

bool write_all(int fd, const std::vector<uint8_t>& bytes) {
  return ::write(fd, bytes.data(), bytes.size()) == static_cast<ssize_t>(bytes.size());
}

}  // namespace

FunctionFsLink::FunctionFsLink(std::string mount_dir) : dir_(std::move(mount_dir)) {
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
}

FunctionFsLink::~FunctionFsLink() {
  request_stop();
  tx_ready_.notify_all();
  // A thread may sit in a blocking FunctionFS call: signal them all until each has seen stop_.
  while (running_.load() > 0) {
    for (std::thread* thread : {&events_, &reader_, &writer_}) {
      if (thread->joinable()) pthread_kill(thread->native_handle(), SIGUSR2);
    }
    tx_ready_.notify_all();
    usleep(1000);
  }
  for (std::thread* thread : {&events_, &reader_, &writer_}) {
    if (thread->joinable()) thread->join();
  }
  for (int fd : {in_, out_, ep0_, wake_fd_}) {
    if (fd >= 0) close(fd);
  }
}

bool FunctionFsLink::start(std::string* error) {
  if (wake_fd_ < 0) {
    *error = std::string("eventfd: ") + std::strerror(errno);
    return false;
  }
  ep0_ = open((dir_ + "/ep0").c_str(), O_RDWR | O_CLOEXEC);
  if (ep0_ < 0) {
    *error = dir_ + "/ep0: " + std::strerror(errno) + " (is a FunctionFS instance mounted there?)";
    return false;
  }
  if (!write_all(ep0_, functionfs_descriptors())) {
    *error = dir_ + "/ep0: FunctionFS refused the descriptors: " + std::strerror(errno);
    return false;
  }
  if (!write_all(ep0_, functionfs_strings())) {
    *error = dir_ + "/ep0: FunctionFS refused the strings: " + std::strerror(errno);
    return false;
  }
  out_ = open((dir_ + "/ep1").c_str(), O_RDONLY | O_CLOEXEC);
  in_ = open((dir_ + "/ep2").c_str(), O_WRONLY | O_CLOEXEC);
  if (out_ < 0 || in_ < 0) {
    *error = dir_ + "/ep1, ep2: " + std::strerror(errno);
    return false;
  }
  install_wake_signal();
  running_.store(3);
  events_ = std::thread(&FunctionFsLink::event_loop, this);
  reader_ = std::thread(&FunctionFsLink::read_loop, this);
  writer_ = std::thread(&FunctionFsLink::write_loop, this);
  return true;
}

void FunctionFsLink::wake() {
  const uint64_t one = 1;
  if (::write(wake_fd_, &one, sizeof one) < 0) {
    // The counter is saturated: the reader is woken already.
  }
}

void FunctionFsLink::drain_wake() {
  uint64_t count = 0;
  while (::read(wake_fd_, &count, sizeof count) > 0) {
  }
}

void FunctionFsLink::request_stop() {
  // Async-signal-safe: an atomic store and a write.
  stop_.store(true);
  wake();
}

void FunctionFsLink::set_enabled(bool enabled) {
  const bool was = enabled_.exchange(enabled);
  if (was && !enabled) {
    drops_.fetch_add(1);
    // What was queued for a host that left would reach the next one as stale bytes; the
    // firmware sends again whatever the host has not acknowledged.
    std::lock_guard<std::mutex> lock(mutex_);
    tx_.clear();
  }
  tx_ready_.notify_all();
}

void FunctionFsLink::event_loop() {
  usb_functionfs_event events[8];
  while (!stop_.load()) {
    const ssize_t got = ::read(ep0_, events, sizeof events);
    if (got <= 0) {
      if (got == 0 || errno != EINTR) usleep(10000);  // not FunctionFS, or it is going away
      continue;
    }
    for (size_t i = 0; i < static_cast<size_t>(got) / sizeof events[0]; ++i) {
      switch (events[i].type) {
        case FUNCTIONFS_ENABLE:
        case FUNCTIONFS_RESUME:
          suspended_.store(false);
          set_enabled(true);
          break;
        case FUNCTIONFS_SUSPEND:
          suspended_.store(true);
          set_enabled(false);
          break;
        case FUNCTIONFS_DISABLE:
        case FUNCTIONFS_UNBIND:
          set_enabled(false);
          break;
        case FUNCTIONFS_SETUP: {
          // The interface has no class or vendor requests of its own: stall, which FunctionFS
          // does when ep0 is used against the request's direction.
          const usb_ctrlrequest& setup = events[i].u.setup;
          char none = 0;
          if (setup.bRequestType & USB_DIR_IN) {
            (void)!::read(ep0_, &none, 0);
          } else {
            (void)!::write(ep0_, &none, 0);
          }
          break;
        }
        default:  // BIND
          break;
      }
    }
  }
  running_.fetch_sub(1);
}

void FunctionFsLink::read_loop() {
  uint8_t buffer[4096];
  while (!stop_.load()) {
    // Blocks until the host is there and sends; fails when it leaves mid-read.
    const ssize_t got = ::read(out_, buffer, sizeof buffer);
    if (got > 0) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        rx_.insert(rx_.end(), buffer, buffer + got);
      }
      wake();
    } else if (got < 0 && errno != EINTR) {
      usleep(1000);  // ESHUTDOWN while the host goes: the next read waits for it to return
    }
  }
  running_.fetch_sub(1);
}

void FunctionFsLink::write_loop() {
  std::vector<uint8_t> chunk;
  while (!stop_.load()) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      tx_ready_.wait(lock, [&] { return stop_.load() || (!tx_.empty() && enabled_.load()); });
      if (stop_.load()) break;
      size_t n = std::min(tx_.size(), kWriteChunk);
      if (n % kPacketDivisor == 0) --n;  // end on a short packet (see kWriteChunk)
      chunk.assign(tx_.begin(), tx_.begin() + static_cast<std::ptrdiff_t>(n));
      tx_.erase(tx_.begin(), tx_.begin() + static_cast<std::ptrdiff_t>(n));
    }
    size_t sent = 0;
    while (sent < chunk.size() && !stop_.load()) {
      const ssize_t put = ::write(in_, chunk.data() + sent, chunk.size() - sent);
      if (put > 0) {
        sent += static_cast<size_t>(put);
      } else if (put < 0 && errno != EINTR) {
        break;  // the host left: these bytes are lost with it, the firmware resends what counts
      }
    }
  }
  running_.fetch_sub(1);
}

size_t FunctionFsLink::write(const uint8_t* data, size_t size) {
  // No host has the interface: refuse, as a device's full IN FIFO would.
  if (!enabled_.load()) return 0;
  size_t taken = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    taken = std::min(size, kTxCapacity - std::min(kTxCapacity, tx_.size()));
    tx_.insert(tx_.end(), data, data + taken);
  }
  if (taken > 0) tx_ready_.notify_one();
  return taken;
}

size_t FunctionFsLink::read(uint8_t* data, size_t capacity) {
  std::lock_guard<std::mutex> lock(mutex_);
  const size_t n = std::min(capacity, rx_.size());
  std::copy_n(rx_.begin(), n, data);
  rx_.erase(rx_.begin(), rx_.begin() + static_cast<std::ptrdiff_t>(n));
  return n;
}

bool FunctionFsLink::wait_readable(int timeout_ms) {
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!rx_.empty()) return true;
    }
    if (stop_.load()) return false;
    pollfd fd{wake_fd_, POLLIN, 0};
    const int ready = poll(&fd, 1, timeout_ms);
    if (ready == 0) return false;
    if (ready > 0) drain_wake();
  }
}

}  // namespace dg::gadget
