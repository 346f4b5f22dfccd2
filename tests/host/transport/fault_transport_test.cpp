// Fault injection: the options parse strictly, and the faults happen at about their rates.
#include "host/transport/fault_transport.h"

#include <CppUTest/TestHarness.h>

#include <chrono>
#include <vector>

using namespace dg::host;

namespace {

// An in-memory line: what is written is what is read.
class Loopback final : public Transport {
 public:
  void write(const uint8_t* data, size_t size) override { bytes.insert(bytes.end(), data, data + size); ++writes; }
  size_t read(uint8_t*, size_t, int) override { return 0; }
  std::string describe() const override { return "loopback"; }
  bool reconnectable() const override { return true; }
  void reconnect() override { ++reconnects; }
  void disconnect() override { ++disconnects; }
  std::vector<uint8_t> bytes;
  int writes = 0, reconnects = 0, disconnects = 0;
};

}  // namespace

TEST_GROUP(FaultTransport){};

TEST(FaultTransport, ParsesItsOptionsStrictly) {
  const FaultSpec s = parse_fault_spec("corrupt=0.001,drop=0.01,dup=0.02,outages=3,outage_ms=200,every=150,seed=5");
  DOUBLES_EQUAL(0.001, s.corrupt, 0);
  DOUBLES_EQUAL(0.02, s.duplicate, 0);
  LONGS_EQUAL(3, s.outages);
  LONGS_EQUAL(5, s.seed);
  CHECK_THROWS(std::invalid_argument, parse_fault_spec("lose=0.1"));
  CHECK_THROWS(std::invalid_argument, parse_fault_spec("drop=x"));
  CHECK_THROWS(std::invalid_argument, parse_fault_spec("drop=2"));
}

TEST(FaultTransport, DropsAndRepeatsFramesAtTheirRates) {
  auto inner = std::make_unique<Loopback>();
  Loopback* line = inner.get();
  FaultSpec spec;
  spec.drop = 0.1;
  spec.duplicate = 0.1;
  FaultTransport faulty(std::move(inner), spec);
  const uint8_t frame[8] = {0, 1, 2, 3, 4, 5, 6, 0};
  for (int k = 0; k < 10000; ++k) faulty.write(frame, sizeof frame);
  CHECK(faulty.counters().dropped > 800 && faulty.counters().dropped < 1200);
  CHECK(faulty.counters().duplicated > 700 && faulty.counters().duplicated < 1100);
  LONGS_EQUAL(10000 - faulty.counters().dropped + faulty.counters().duplicated, line->writes);
}

TEST(FaultTransport, PullsTheCableAndLetsItBePluggedBackIn) {
  auto inner = std::make_unique<Loopback>();
  Loopback* line = inner.get();
  FaultTransport faulty(std::move(inner), parse_fault_spec("disconnects=2,every=10"));
  const uint8_t frame[4] = {1, 2, 3, 0};
  int pulled = 0;
  for (int k = 0; k < 100; ++k) {
    try {
      faulty.write(frame, sizeof frame);
    } catch (const TransportError& e) {
      ++pulled;
      STRCMP_CONTAINS("cable pulled", e.what());
      // Dead until plugged back in, as a real pulled cable.
      uint8_t buffer[4];
      CHECK_THROWS(TransportError, faulty.read(buffer, sizeof buffer, 0));
      CHECK_THROWS(TransportError, faulty.write(frame, sizeof frame));
      CHECK(faulty.reconnectable());
      faulty.reconnect();
    }
  }
  LONGS_EQUAL(2, pulled);
  LONGS_EQUAL(2, line->disconnects);
  LONGS_EQUAL(2, line->reconnects);
  LONGS_EQUAL(2, faulty.counters().disconnects);
}

TEST(FaultTransport, HoldsBackSomeFramesForAWhile) {
  auto inner = std::make_unique<Loopback>();
  Loopback* line = inner.get();
  FaultTransport faulty(std::move(inner), parse_fault_spec("delay=0.5,delay_ms=2"));
  const uint8_t frame[4] = {1, 2, 3, 0};
  const auto started = std::chrono::steady_clock::now();
  for (int k = 0; k < 40; ++k) faulty.write(frame, sizeof frame);
  const auto spent = std::chrono::steady_clock::now() - started;
  CHECK(faulty.counters().delayed > 10 && faulty.counters().delayed < 30);
  CHECK(spent >= std::chrono::milliseconds(2 * faulty.counters().delayed));
  LONGS_EQUAL(40, line->writes);  // late, never lost
}
