// Parses a device URI and opens the matching transport.
#include <stdexcept>
#include <vector>

#include "host/transport/fault_transport.h"
#include "host/transport/sim_transport.h"
#include "host/transport/socket_transport.h"
#include "host/transport/usb_transport.h"
#include "host/transport/transport.h"

namespace dg::host {

std::unique_ptr<Transport> open_transport(const std::string& uri) {
  const size_t colon = uri.find(':');
  if (colon == std::string::npos) {
    throw std::invalid_argument("device URI '" + uri + "' has no scheme (try sim:part=dome)");
  }
  const std::string scheme = uri.substr(0, colon);
  const std::string rest = uri.substr(colon + 1);
  if (scheme == "fault") {
    // fault:OPTIONS;INNER-URI wraps another transport in fault injection.
    const size_t semicolon = rest.find(';');
    if (semicolon == std::string::npos) {
      throw std::invalid_argument("device URI '" + uri + "': fault: needs OPTIONS;URI, e.g. fault:drop=0.01;sim:part=dome");
    }
    return std::make_unique<FaultTransport>(open_transport(rest.substr(semicolon + 1)), parse_fault_spec(rest.substr(0, semicolon)));
  }
  if (scheme == "sim") {
    std::vector<std::string> options;
    size_t start = 0;
    while (start < rest.size()) {
      size_t comma = rest.find(',', start);
      if (comma == std::string::npos) comma = rest.size();
      const std::string pair = rest.substr(start, comma - start);
      if (!pair.empty()) {
        if (pair.find('=') == std::string::npos) {
          throw std::invalid_argument("device URI '" + uri + "': option '" + pair +
                                      "' is not key=value");
        }
        options.push_back(pair);
      }
      start = comma + 1;
    }
    return std::make_unique<SimTransport>(uri, options);
  }
  if (scheme == "unix" || scheme == "tcp") return std::make_unique<SocketTransport>(uri);
  if (scheme == "usb") return std::make_unique<UsbTransport>(uri);
  throw std::invalid_argument("device URI '" + uri + "': unknown scheme '" + scheme +
                              "' (this build knows sim:, usb:, unix:, tcp: and fault:)");
}

}  // namespace dg::host
