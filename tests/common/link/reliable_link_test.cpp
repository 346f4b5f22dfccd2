// The reliable link in isolation: two endpoints over a channel that loses, duplicates, reorders
// and corrupts frames; every payload must arrive exactly once, in order.
#include "common/link/reliable_link.h"

#include <CppUTest/TestHarness.h>

#include <cstring>
#include <deque>
#include <random>
#include <vector>

namespace {

using Link = dg::ReliableLink<4>;

struct Faults {
  double drop = 0, duplicate = 0, reorder = 0, corrupt_byte = 0;
};

// One direction of the wire: frames in flight, with faults applied as they enter.
class Channel {
 public:
  Channel(Faults faults, unsigned seed) : faults_(faults), rng_(seed) {}
  void put(const uint8_t* wire, size_t size) {
    std::vector<uint8_t> frame(wire, wire + size);
    if (chance(faults_.drop)) return;
    for (auto& b : frame)
      if (chance(faults_.corrupt_byte)) b ^= static_cast<uint8_t>(1 + rng_() % 255);
    if (chance(faults_.reorder) && !queue_.empty()) {
      queue_.insert(queue_.end() - 1, frame);
    } else {
      queue_.push_back(frame);
    }
    if (chance(faults_.duplicate)) queue_.push_back(frame);
  }
  bool take(std::vector<uint8_t>& frame) {
    if (queue_.empty()) return false;
    frame = queue_.front();
    queue_.pop_front();
    return true;
  }

 private:
  bool chance(double p) { return std::uniform_real_distribution<double>(0, 1)(rng_) < p; }
  Faults faults_;
  std::mt19937 rng_;
  std::deque<std::vector<uint8_t>> queue_;
};

struct Endpoint {
  Link link{20000};
  dg::FrameDecoder decoder;
  std::vector<uint32_t> received;
  uint32_t next_to_send = 0;
};

// Runs until `count` payloads went from a to b (and b's acks back), or `max_ms` of simulated time.
void exchange(Endpoint& a, Endpoint& b, uint32_t count, Faults faults, uint64_t max_ms = 200000) {
  Channel ab(faults, 1), ba(faults, 2);
  uint8_t wire[dg::kFrameMaxWire];
  for (uint64_t now_us = 0; now_us < max_ms * 1000; now_us += 1000) {
    while (a.next_to_send < count) {
      uint8_t payload[4];
      std::memcpy(payload, &a.next_to_send, 4);
      if (a.link.send(payload, 4, now_us) != dg::Status::kOk) break;
      ++a.next_to_send;
    }
    size_t size = 0;
    for (int k = 0; k < 8 && a.link.next_frame(now_us, wire, sizeof wire, &size); ++k) ab.put(wire, size);
    for (int k = 0; k < 8 && b.link.next_frame(now_us, wire, sizeof wire, &size); ++k) ba.put(wire, size);
    auto deliver = [now_us](Channel& channel, Endpoint& to) {
      std::vector<uint8_t> frame;
      while (channel.take(frame)) {
        size_t offset = 0;
        while (offset < frame.size()) {
          size_t used = 0;
          const dg::Status s = to.decoder.feed(frame.data() + offset, frame.size() - offset, &used);
          offset += used;
          if (s == dg::Status::kNeedMore) break;
          if (s != dg::Status::kOk) continue;
          if (to.link.receive(to.decoder.header(), now_us) && to.decoder.payload_size() == 4) {
            uint32_t value;
            std::memcpy(&value, to.decoder.payload(), 4);
            to.received.push_back(value);
          }
        }
      }
    };
    deliver(ab, b);
    deliver(ba, a);
    if (b.received.size() == count && a.link.all_acknowledged()) return;
  }
}

void check_exactly_once_in_order(const Endpoint& b, uint32_t count) {
  LONGS_EQUAL(count, b.received.size());
  for (uint32_t i = 0; i < b.received.size(); ++i) LONGS_EQUAL(i, b.received[i]);
}

}  // namespace

TEST_GROUP(ReliableLink){};

TEST(ReliableLink, DeliversInOrderOverACleanChannel) {
  Endpoint a, b;
  exchange(a, b, 500, Faults{});
  check_exactly_once_in_order(b, 500);
  LONGS_EQUAL(0, a.link.counters().retransmitted);
  CHECK(a.link.all_acknowledged());
}

TEST(ReliableLink, RecoversFromLossDuplicationReorderingAndCorruption) {
  Endpoint a, b;
  Faults f;
  f.drop = 0.05;
  f.duplicate = 0.05;
  f.reorder = 0.05;
  f.corrupt_byte = 0.002;
  exchange(a, b, 3000, f);
  check_exactly_once_in_order(b, 3000);
  CHECK(a.link.counters().retransmitted > 0);
  CHECK(b.link.counters().duplicates + b.link.counters().out_of_order > 0);
  CHECK(a.link.all_acknowledged());
}

TEST(ReliableLink, AFullWindowPushesBackUntilAcknowledged) {
  Link link;
  const uint8_t payload[1] = {7};
  for (int i = 0; i < 4; ++i) CHECK(dg::Status::kOk == link.send(payload, 1, 0));
  CHECK(link.window_full());
  CHECK(dg::Status::kBusy == link.send(payload, 1, 0));
  dg::FrameHeader ack;
  ack.kind = dg::FrameKind::kAckOnly;
  ack.ack = 2;
  link.receive(ack, 0);
  LONGS_EQUAL(2, link.in_flight());
  CHECK(dg::Status::kOk == link.send(payload, 1, 0));
}

// A device encodes its message straight into the next slot: nothing to write into while the window
// is full, and what was written there goes out as the next frame, exactly as send() would send it.
TEST(ReliableLink, AMessageEncodedIntoTheNextSlotIsSentAsTheNextFrame) {
  Link link;
  const uint8_t payload[3] = {1, 0, 2};
  for (int i = 0; i < 3; ++i) CHECK(dg::Status::kOk == link.send(payload, 3, 0));
  uint8_t* slot = link.next_payload();
  CHECK(slot != nullptr);
  slot[0] = 9, slot[1] = 8;
  CHECK(dg::Status::kOk == link.commit(2, 0));
  CHECK(link.window_full());
  CHECK(link.next_payload() == nullptr);
  CHECK(dg::Status::kBusy == link.commit(1, 0));
  uint8_t wire[dg::kFrameMaxWire];
  size_t size = 0;
  for (int frame = 0; frame < 4; ++frame) CHECK(link.next_frame(0, wire, sizeof wire, &size));
  // The last frame out is the fourth: sequence 4 carrying 9, 8.
  dg::FrameDecoder decoder;
  size_t consumed = 0;
  CHECK(dg::Status::kOk == decoder.feed(wire, size, &consumed));
  LONGS_EQUAL(4, decoder.header().seq);
  LONGS_EQUAL(2, decoder.payload_size());
  LONGS_EQUAL(9, decoder.payload()[0]);
  LONGS_EQUAL(8, decoder.payload()[1]);
}

TEST(ReliableLink, RetransmitsOnlyAfterTheTimeout) {
  Link link(50000);
  const uint8_t payload[1] = {1};
  link.send(payload, 1, 0);
  uint8_t wire[dg::kFrameMaxWire];
  size_t size = 0;
  CHECK(link.next_frame(0, wire, sizeof wire, &size));
  CHECK_FALSE(link.next_frame(49999, wire, sizeof wire, &size));
  CHECK(link.next_frame(50000, wire, sizeof wire, &size));
  LONGS_EQUAL(1, link.counters().retransmitted);
  // No answer to the first copy: the next waits twice as long.
  LONGS_EQUAL(150000, link.next_deadline_us(~0ull));
}

TEST(ReliableLink, TheTimeoutFollowsTheMeasuredRoundTripSoASlowLineIsNotFlooded) {
  Link link(50000);
  uint8_t wire[dg::kFrameMaxWire];
  size_t size = 0;
  const uint8_t payload[1] = {1};
  dg::FrameHeader ack;
  ack.kind = dg::FrameKind::kAckOnly;
  // Acknowledgements come 120 ms after each frame: more than the 50 ms the link starts with.
  uint64_t now_us = 0;
  uint16_t seq = 1;
  for (int i = 0; i < 20; ++i, ++seq) {
    CHECK(dg::Status::kOk == link.send(payload, 1, now_us));
    CHECK(link.next_frame(now_us, wire, sizeof wire, &size));
    now_us += 120000;
    // Before the round trip is known the timer fires (and its copy's ack measures nothing);
    // the next frame still finds the doubled timeout short, but from its ack on it is long enough.
    if (i == 0) CHECK(link.next_frame(now_us, wire, sizeof wire, &size));
    if (i >= 2) CHECK_FALSE(link.next_frame(now_us, wire, sizeof wire, &size));
    ack.ack = seq;
    link.receive(ack, now_us);
  }
  LONGS_EQUAL(1, link.counters().retransmitted);
  CHECK(link.timeout_us() >= 120000);
  CHECK(link.timeout_us() <= 16 * 50000);
  // A fast line again: the timeout comes back down, never below the configured 50 ms.
  for (int i = 0; i < 40; ++i, ++seq) {
    CHECK(dg::Status::kOk == link.send(payload, 1, now_us));
    CHECK(link.next_frame(now_us, wire, sizeof wire, &size));
    now_us += 1000;
    ack.ack = seq;
    link.receive(ack, now_us);
  }
  LONGS_EQUAL(50000, link.timeout_us());
}

TEST(ReliableLink, SurvivesTheSequenceNumberWrap) {
  Endpoint a, b;
  exchange(a, b, 70000, Faults{}, 400000);
  check_exactly_once_in_order(b, 70000);
}

TEST(ReliableLink, AnswersADuplicateWithAnAck) {
  Link receiver;
  dg::FrameHeader data;
  data.kind = dg::FrameKind::kData;
  data.seq = 1;
  CHECK(receiver.receive(data, 0));
  uint8_t wire[dg::kFrameMaxWire];
  size_t size = 0;
  CHECK(receiver.next_frame(0, wire, sizeof wire, &size));  // the ack
  CHECK_FALSE(receiver.receive(data, 0));                  // the same frame again
  LONGS_EQUAL(1, receiver.counters().duplicates);
  CHECK(receiver.next_frame(0, wire, sizeof wire, &size));  // acknowledged again
  LONGS_EQUAL(2, receiver.counters().acks_sent);
}

TEST(ReliableLink, ASyncFrameStartsANewSessionOnceAndDropsTheOldOnesFrames) {
  Link host, device;
  uint8_t wire[dg::kFrameMaxWire];
  size_t size = 0;
  dg::FrameDecoder at_device, at_host;
  auto carry = [&](Link& from, dg::FrameDecoder& decoder, Link& to, uint64_t now) {
    int delivered = 0;
    while (from.next_frame(now, wire, sizeof wire, &size)) {
      size_t used = 0;
      if (decoder.feed(wire, size, &used) == dg::Status::kOk && to.receive(decoder.header(), now)) ++delivered;
    }
    return delivered;
  };
  const uint8_t hello[1] = {1};
  CHECK(dg::Status::kOk == host.send_sync(hello, 1, 0, 0x1234));
  LONGS_EQUAL(1, carry(host, at_device, device, 0));
  CHECK(device.take_restart());
  CHECK_FALSE(device.take_restart());
  // The device has frames in flight when the host goes away.
  const uint8_t point[1] = {2};
  device.send(point, 1, 0);
  device.send(point, 1, 0);
  CHECK(device.next_frame(0, wire, sizeof wire, &size));
  // A new host: a new session id. The device forgets its two frames and takes the new sync.
  Link new_host;
  CHECK(dg::Status::kOk == new_host.send_sync(hello, 1, 1000, 0x4321));
  LONGS_EQUAL(1, carry(new_host, at_device, device, 1000));
  CHECK(device.take_restart());
  CHECK(device.all_acknowledged());
  // The same sync again (a retransmission) is a duplicate, not another restart.
  CHECK(new_host.next_frame(200000, wire, sizeof wire, &size));
  size_t used = 0;
  CHECK(dg::Status::kOk == at_device.feed(wire, size, &used));
  CHECK_FALSE(device.receive(at_device.header(), 0));
  CHECK_FALSE(device.take_restart());
}

TEST(ReliableLink, AFrameSentBeforeTheSessionIsNotTakenForItsFirst) {
  Link host, device;
  dg::FrameDecoder at_device, at_host;
  uint8_t wire[dg::kFrameMaxWire];
  size_t size = 0, used = 0;
  // Power-up: the device raises an alarm before any host is there; the frame waits in the pipe.
  const uint8_t alarm[1] = {9};
  device.send(alarm, 1, 0);
  uint8_t stale[dg::kFrameMaxWire];
  size_t stale_size = 0;
  CHECK(device.next_frame(0, stale, sizeof stale, &stale_size));
  // A host opens a session; the device takes it and answers.
  const uint8_t hello[1] = {1};
  CHECK(dg::Status::kOk == host.send_sync(hello, 1, 0, 0x2345));
  CHECK(host.next_frame(0, wire, sizeof wire, &size));
  CHECK(dg::Status::kOk == at_device.feed(wire, size, &used));
  CHECK(device.receive(at_device.header(), 0));
  const uint8_t reply[1] = {2};
  device.send(reply, 1, 0);
  CHECK(device.next_frame(0, wire, sizeof wire, &size));
  // The stale alarm reaches the host first: dropped, and the reply after it is delivered.
  CHECK(dg::Status::kOk == at_host.feed(stale, stale_size, &used));
  CHECK_FALSE(host.receive(at_host.header(), 0));
  CHECK(dg::Status::kOk == at_host.feed(wire, size, &used));
  CHECK(host.receive(at_host.header(), 0));
  LONGS_EQUAL(2, at_host.payload()[0]);
}

TEST(ReliableLink, TwoAcksThatFreeNothingResendBeforeTheTimer) {
  Link link(50000);
  const uint8_t payload[1] = {1};
  link.send(payload, 1, 0);
  link.send(payload, 1, 0);
  uint8_t wire[dg::kFrameMaxWire];
  size_t size = 0;
  CHECK(link.next_frame(0, wire, sizeof wire, &size));
  CHECK(link.next_frame(0, wire, sizeof wire, &size));
  CHECK_FALSE(link.next_frame(10, wire, sizeof wire, &size));
  // The other side got frame 2 but not 1: it answers with ack 0, twice (once is not enough).
  dg::FrameHeader nothing;
  nothing.kind = dg::FrameKind::kAckOnly;
  nothing.ack = 0;
  link.receive(nothing, 0);
  CHECK_FALSE(link.next_frame(20, wire, sizeof wire, &size));
  link.receive(nothing, 0);
  CHECK(link.next_frame(30, wire, sizeof wire, &size));
  LONGS_EQUAL(1, link.counters().fast_retransmits);
  LONGS_EQUAL(1, link.counters().retransmitted);
}

TEST(ReliableLink, FramesKeptAheadOfAGapAreDeliveredAndAcknowledgedOnceItFills) {
  Link receiver;
  dg::FrameHeader data;
  data.kind = dg::FrameKind::kData;
  // Frame 1 is lost; 2 and 3 arrive first and a receiver with memory keeps them.
  data.seq = 2;
  CHECK_FALSE(receiver.receive(data, 0));
  data.seq = 3;
  CHECK_FALSE(receiver.receive(data, 0));
  LONGS_EQUAL(1, receiver.expected_seq());
  data.seq = 1;
  CHECK(receiver.receive(data, 0));
  LONGS_EQUAL(2, receiver.expected_seq());
  receiver.deliver_kept();  // 2
  receiver.deliver_kept();  // 3
  LONGS_EQUAL(4, receiver.expected_seq());
  LONGS_EQUAL(3, receiver.counters().delivered);
  // One acknowledgement covers all three, so the sender need not send 2 and 3 again.
  uint8_t wire[dg::kFrameMaxWire];
  size_t size = 0;
  CHECK(receiver.next_frame(0, wire, sizeof wire, &size));
  dg::FrameDecoder decoder;
  size_t used = 0;
  CHECK(dg::Status::kOk == decoder.feed(wire, size, &used));
  CHECK(decoder.header().kind == dg::FrameKind::kAckOnly);
  LONGS_EQUAL(3, decoder.header().ack);
  // Frame 2 sent again after all is an old duplicate.
  data.seq = 2;
  CHECK_FALSE(receiver.receive(data, 0));
  LONGS_EQUAL(1, receiver.counters().duplicates);
}
