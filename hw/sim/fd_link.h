// LinkPort over a connected stream socket or pipe pair (the host's end of the sim: transport).
#pragma once
#include "hw/sim/sim_board.h"

namespace dg::sim {

class FdLink final : public LinkPort {
 public:
  FdLink(int read_fd, int write_fd);
  size_t write(const uint8_t* data, size_t size) override;
  size_t read(uint8_t* data, size_t capacity) override;
  bool wait_readable(int timeout_ms = -1) override;
  bool closed() const override { return closed_; }

 private:
  int read_fd_;
  int write_fd_;
  bool closed_ = false;
};

}  // namespace dg::sim
