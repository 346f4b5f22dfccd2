// sim: transport: starts digitizer-sim as a child process and talks over a socket pair.
#pragma once
#include <sys/types.h>

#include <string>
#include <vector>

#include "host/transport/transport.h"

namespace dg::host {

class SimTransport final : public Transport {
 public:
  // `options` are the URI's key=value pairs, passed to the simulator unchanged.
  SimTransport(const std::string& uri, const std::vector<std::string>& options);
  ~SimTransport() override;
  SimTransport(const SimTransport&) = delete;
  SimTransport& operator=(const SimTransport&) = delete;

  void write(const uint8_t* data, size_t size) override;
  size_t read(uint8_t* data, size_t capacity, int timeout_ms) override;
  std::string describe() const override { return uri_; }

 private:
  std::string child_exit_reason();
  // Waits up to timeout_ms for the simulator to exit; true (and its status) if it did.
  bool reap_child(int timeout_ms, int* status);

  std::string uri_;
  int fd_ = -1;
  pid_t child_ = -1;
};

// Where digitizer-sim is: $DIGITIZER_SIM, else next to the running program.
std::string find_simulator();

}  // namespace dg::host
