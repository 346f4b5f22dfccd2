// unix: and tcp: URIs: strict parsing, clear errors for a device that is not there, and bytes
// both ways with a reconnect through a real socket.
#include "host/transport/socket_transport.h"

#include <CppUTest/TestHarness.h>

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <string>

using namespace dg::host;

namespace {

std::string socket_path(const char* name) {
  return std::string(P_tmpdir) + "/dg_socket_" + std::to_string(getpid()) + "_" + name;
}

// A listening unix socket that accepts one connection at a time.
struct Listener {
  explicit Listener(const std::string& path) : path(path) {
    fd = socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(address.sun_path, path.c_str(), sizeof(address.sun_path) - 1);
    unlink(path.c_str());
    CHECK(bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0);
    CHECK(listen(fd, 2) == 0);
  }
  ~Listener() {
    close(fd);
    unlink(path.c_str());
  }
  std::string path;
  int fd = -1;
};

}  // namespace

TEST_GROUP(SocketTransport){};

TEST(SocketTransport, RejectsMalformedUris) {
  CHECK_THROWS(std::invalid_argument, SocketTransport("unix:"));
  CHECK_THROWS(std::invalid_argument, SocketTransport("tcp:localhost"));
  CHECK_THROWS(std::invalid_argument, SocketTransport("tcp::5555"));
  CHECK_THROWS(std::invalid_argument, SocketTransport("tcp:host:"));
  CHECK_THROWS(std::invalid_argument, SocketTransport("unix:" + std::string(200, 'x')));
}

TEST(SocketTransport, ADeviceThatIsNotThereIsAnErrorNamingIt) {
  std::string error;
  try {
    SocketTransport transport("unix:" + socket_path("absent"));
  } catch (const TransportError& e) {
    error = e.what();
  }
  STRCMP_CONTAINS("dg_socket_", error.c_str());
  STRCMP_CONTAINS("cannot connect", error.c_str());
  error.clear();
  try {
    SocketTransport transport("tcp:no-such-host.invalid:5555");
  } catch (const TransportError& e) {
    error = e.what();
  }
  STRCMP_CONTAINS("tcp:no-such-host.invalid:5555", error.c_str());
}

TEST(SocketTransport, CarriesBytesBothWaysAndReconnectsAfterTheOtherEndCloses) {
  Listener listener(socket_path("echo"));
  SocketTransport transport("unix:" + listener.path);
  CHECK(transport.reconnectable());
  int device = accept(listener.fd, nullptr, nullptr);
  const uint8_t hello[3] = {1, 2, 3};
  transport.write(hello, sizeof hello);
  uint8_t got[8] = {};
  LONGS_EQUAL(3, read(device, got, sizeof got));
  LONGS_EQUAL(3, got[2]);
  LONGS_EQUAL(2, write(device, hello, 2));
  LONGS_EQUAL(2, transport.read(got, sizeof got, 1000));
  LONGS_EQUAL(0, transport.read(got, sizeof got, 10));  // nothing more: a timeout, not an error
  // The device end goes away: the next read says so.
  close(device);
  CHECK_THROWS(TransportError, transport.read(got, sizeof got, 1000));
  transport.reconnect();
  device = accept(listener.fd, nullptr, nullptr);
  transport.write(hello, 1);
  LONGS_EQUAL(1, read(device, got, sizeof got));
  close(device);
}
