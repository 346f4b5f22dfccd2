// sim: transport: starts digitizer-sim as a child process and talks over a socket pair.
#pragma once
#include <sys/types.h>

#include <string>
#include <vector>

#include "host/transport/fd_transport.h"

namespace dg::host {

class SimTransport final : public FdTransport {
 public:
  // `options` are the URI's key=value pairs, passed to the simulator unchanged.
  SimTransport(const std::string& uri, const std::vector<std::string>& options);
  ~SimTransport() override;

 private:
  std::string closed_reason() override;
  // Waits up to timeout_ms for the simulator to exit; true (and its status) if it did.
  bool reap_child(int timeout_ms, int* status);

  pid_t child_ = -1;
};

// Where digitizer-sim is: $DIGITIZER_SIM, else next to the running program.
std::string find_simulator();

}  // namespace dg::host
