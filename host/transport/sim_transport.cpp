// Spawns the simulated device; the socket pair gives it a byte stream like a USB pipe.
#include "host/transport/sim_transport.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace dg::host {

std::string find_simulator() {
  if (const char* env = std::getenv("DIGITIZER_SIM"); env != nullptr && *env != '\0') return env;
  char self[PATH_MAX] = {};
  const ssize_t n = readlink("/proc/self/exe", self, sizeof(self) - 1);
  if (n > 0) {
    std::string dir(self, static_cast<size_t>(n));
    dir = dir.substr(0, dir.rfind('/'));
    const std::string candidate = dir + "/digitizer-sim";
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return "digitizer-sim";  // fall back to PATH
}

SimTransport::SimTransport(const std::string& uri, const std::vector<std::string>& options)
    : FdTransport(uri) {
  // A device that dies must be an error message, not a SIGPIPE.
  signal(SIGPIPE, SIG_IGN);
  int sv[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) {
    throw TransportError(uri + ": cannot create socket pair: " + std::strerror(errno));
  }
  const std::string program = find_simulator();
  std::vector<std::string> args = {program, "--fd", "3"};
  args.insert(args.end(), options.begin(), options.end());
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  child_ = fork();
  if (child_ < 0) {
    close(sv[0]);
    close(sv[1]);
    throw TransportError(uri + ": cannot start the simulator: " + std::strerror(errno));
  }
  if (child_ == 0) {
    // dup2 clears close-on-exec on the copy, but does nothing if the socket already
    // is fd 3 (when the parent runs with stdin closed), so clear it by hand then.
    if (sv[1] == 3) {
      fcntl(3, F_SETFD, 0);
    } else {
      dup2(sv[1], 3);
    }
    execvp(argv[0], argv.data());
    std::fprintf(stderr, "digitizer: cannot run %s: %s\n", argv[0], std::strerror(errno));
    _exit(127);
  }
  close(sv[1]);
  adopt(sv[0]);
}

bool SimTransport::reap_child(int timeout_ms, int* status) {
  for (int waited_ms = 0; child_ > 0; waited_ms += 5) {
    if (waitpid(child_, status, WNOHANG) == child_) {
      child_ = -1;
      return true;
    }
    if (waited_ms >= timeout_ms) return false;
    usleep(5000);
  }
  return false;
}

SimTransport::~SimTransport() {
  disconnect();  // the simulator exits when its link closes
  int status = 0;
  if (child_ > 0 && !reap_child(1000, &status)) {
    kill(child_, SIGKILL);
    waitpid(child_, &status, 0);
  }
}

std::string SimTransport::closed_reason() {
  // The link closed because the simulator is exiting: wait for it to say how.
  int status = 0;
  if (reap_child(1000, &status)) {
    if (WIFEXITED(status)) return "simulator exited with status " + std::to_string(WEXITSTATUS(status));
    if (WIFSIGNALED(status)) return "simulator killed by signal " + std::to_string(WTERMSIG(status));
  }
  return "device closed the link";
}

}  // namespace dg::host
