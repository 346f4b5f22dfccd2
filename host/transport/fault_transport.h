// A transport that damages the bytes of another: corruption, lost and repeated frames, outages
// (a pulled cable that comes back). It wraps any transport, for tests and for trying a link.
#pragma once
#include <chrono>
#include <memory>
#include <random>
#include <string>

#include "host/transport/transport.h"

namespace dg::host {

struct FaultSpec {
  double corrupt = 0;    // probability that a byte, either direction, is flipped
  double drop = 0;       // probability that a written frame (one write) or a read chunk is lost
  double duplicate = 0;  // probability that a written frame goes out twice
  int outages = 0;       // how many times the line goes dead
  int outage_ms = 300;   // for how long
  int outage_every = 400;  // writes between outages, and between forced disconnects
  double delay = 0;      // probability that a written frame is held back (a busy bus, a slow hub)
  int delay_ms = 20;     // for how long
  int disconnects = 0;     // how many times the cable is pulled (the link closes; reconnect() restores it)
  unsigned seed = 1;
};

// Parses "corrupt=0.001,drop=0.01,dup=0.01,delay=0.01,delay_ms=20,outages=3,outage_ms=300,every=400,
// disconnects=3,seed=7"; throws
// std::invalid_argument naming a bad key or value.
FaultSpec parse_fault_spec(const std::string& text);

class FaultTransport final : public Transport {
 public:
  FaultTransport(std::unique_ptr<Transport> inner, const FaultSpec& spec);
  void write(const uint8_t* data, size_t size) override;
  size_t read(uint8_t* data, size_t capacity, int timeout_ms) override;
  std::string describe() const override;
  bool reconnectable() const override { return inner_->reconnectable(); }
  void reconnect() override;
  void disconnect() override;

  struct Counters {
    uint64_t corrupted = 0, dropped = 0, duplicated = 0, delayed = 0, outages = 0, disconnects = 0;
  };
  const Counters& counters() const { return counters_; }

 private:
  bool chance(double p);
  bool in_outage();

  std::unique_ptr<Transport> inner_;
  FaultSpec spec_;
  std::mt19937 rng_;
  Counters counters_;
  uint64_t writes_ = 0;
  int outages_left_;
  int disconnects_left_;
  bool disconnected_ = false;
  std::chrono::steady_clock::time_point outage_end_{};
};

}  // namespace dg::host
