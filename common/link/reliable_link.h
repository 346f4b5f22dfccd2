// The reliable link over frames: every data frame numbered, cumulative acknowledgements,
// retransmission after a timeout (go-back-N), duplicates and out-of-order frames discarded, a
// bounded window that pushes back on the sender. The same class runs on the device and the host;
// it holds no heap memory and throws nothing.
//
// Sessions: the host opens one with send_sync(), whose frame (kind kSync) carries a session id in
// its ack field. A receiver that sees a new id forgets both directions of the old session (the
// frames it still had in flight belong to a host that is gone) and says so through
// take_restart(), so the application can replay what the new host has not confirmed. Copies of
// the same sync frame are ordinary duplicates. Both directions of a session number their frames
// from the session id, not from 1: a USB pipe keeps bytes across hosts, and a frame the device
// sent before this host came (an alarm at power-up, say) must not pass for the new session's first.
#pragma once
#include <cstddef>
#include <cstdint>

#include "common/link/frame.h"
#include "common/status.h"

namespace dg {

struct LinkCounters {
  uint32_t sent = 0;              // data frames sent the first time
  uint32_t retransmitted = 0;     // data frames sent again
  uint32_t delivered = 0;         // payloads handed up, in order, once each
  uint32_t duplicates = 0;        // frames already delivered, dropped
  uint32_t out_of_order = 0;      // frames after a gap, dropped (the sender resends them)
  uint32_t acks_sent = 0;         // ack-only frames
  uint32_t fast_retransmits = 0;  // resends started by repeated acks, before the timer
};

// kWindow frames may be unacknowledged at once; each holds up to kSlotPayload bytes (a board with
// little RAM sends shorter frames than the protocol allows; it receives any).
template <size_t kWindow, size_t kSlotPayload = kFrameMaxPayload>
class ReliableLink {
 public:
  static_assert(kSlotPayload >= 1 && kSlotPayload <= kFrameMaxPayload, "a slot holds at most a frame's payload");
  // A data frame's payload capacity, and the wire bytes its frame may take.
  static constexpr size_t kPayloadCapacity = kSlotPayload;
  static constexpr size_t kWireCapacity = cobs_max_encoded_size(kFrameHeaderSize + kSlotPayload + kFrameCrcSize) + 2;
  // A power of two divides 2^16, so the slots of any kWindow consecutive sequence numbers differ,
  // across the wrap from 65535 to 0 too.
  static_assert(kWindow >= 1 && kWindow <= 16384 && (kWindow & (kWindow - 1)) == 0, "the window must be a power of two");
  static_assert(kSlotPayload <= UINT16_MAX, "a slot keeps its payload size in 16 bits");

  // `retransmit_us` is the shortest retransmission timeout and the one used until round trips
  // have been measured; the timeout then follows the measured round trip (RFC 6298's estimator:
  // smoothed round trip plus four times its mean deviation, never below `retransmit_us` nor above
  // kMaxTimeoutFactor times it) and doubles after each timeout, so a slow line is not flooded with
  // copies of frames that are still on their way.
  static constexpr uint32_t kMaxTimeoutFactor = 16;
  explicit ReliableLink(uint32_t retransmit_us = 50000) : retransmit_us_(retransmit_us), timeout_us_(retransmit_us) {}

  // Forgets everything in flight and starts numbering again (a new session).
  void reset() {
    session_ = 0;
    next_seq_ = 1;
    oldest_ = 1;
    count_ = 0;
    rx_expected_ = 1;
    ack_owed_ = false;
    resending_ = false;
    duplicate_acks_ = 0;
    counters_ = LinkCounters{};
    srtt_us_ = rttvar_us_ = 0;
    timeout_us_ = retransmit_us_;
  }

  bool window_full() const { return count_ == kWindow; }
  bool all_acknowledged() const { return count_ == 0; }
  size_t in_flight() const { return count_; }
  // The retransmission timeout in use now.
  uint32_t timeout_us() const { return timeout_us_; }
  const LinkCounters& counters() const { return counters_; }

  // Queues a payload as the next data frame. kBusy when the window is full: try again once
  // acknowledgements have made room. kOverflow for a payload larger than a frame holds.
  Status send(const uint8_t* payload, size_t size, uint64_t now_us) {
    if (size > kSlotPayload) return Status::kOverflow;
    uint8_t* slot_payload = next_payload();
    if (slot_payload == nullptr) return Status::kBusy;
    for (size_t i = 0; i < size; ++i) slot_payload[i] = payload[i];
    return commit(size, now_us);
  }

  // The next data frame's payload (kPayloadCapacity bytes), for a message to be encoded into in
  // place, or nullptr while the window is full; commit() queues it. A device has no stack to spare
  // for a frame-sized copy.
  uint8_t* next_payload() { return window_full() ? nullptr : slots_[index(next_seq_)].payload; }

  // Queues the `size` bytes written at next_payload() as the next data frame.
  Status commit(size_t size, uint64_t now_us) {
    if (size > kSlotPayload) return Status::kOverflow;
    if (window_full()) return Status::kBusy;
    Slot& slot = slots_[index(next_seq_)];
    slot.size = static_cast<uint16_t>(size);
    slot.seq = next_seq_;
    slot.sent = false;
    slot.resent = false;
    slot.sync = false;
    slot.sent_us = now_us;
    ++next_seq_;
    ++count_;
    return Status::kOk;
  }

  // Starts a new session (`session_id` non-zero, different from the last) with `payload` as its
  // first frame.
  Status send_sync(const uint8_t* payload, size_t size, uint64_t now_us, uint16_t session_id) {
    reset();
    start_session(session_id);
    const Status status = send(payload, size, now_us);
    if (status == Status::kOk) slots_[index(oldest_)].sync = true;
    return status;
  }

  // True once after a frame from the other side started a new session.
  bool take_restart() {
    const bool restarted = restarted_;
    restarted_ = false;
    return restarted;
  }

  // A decoded frame from the other side, arrived at `now_us`. Returns true when its payload is new
  // and in order: the caller hands it up. The ack field frees our acknowledged frames either way
  // and, for a frame sent only once, measures the round trip.
  bool receive(const FrameHeader& header, uint64_t now_us) {
    if (header.kind == FrameKind::kSync) {
      if (header.ack != session_) {
        reset();
        start_session(header.ack);
        rx_expected_ = header.seq;
        restarted_ = true;
      }
    } else {
      const bool progressed = acknowledge(header.ack, now_us);
      // Fast retransmission: an ack-only frame that frees nothing answers a frame that arrived
      // after a gap (or twice). Two of them mean a frame of ours was lost: resend from the oldest
      // now instead of waiting for the timer.
      if (header.kind == FrameKind::kAckOnly && !progressed && count_ > 0) {
        if (++duplicate_acks_ >= 2 && !resending_) {
          resending_ = true;
          resend_next_ = oldest_;
          duplicate_acks_ = 0;
          ++counters_.fast_retransmits;
        }
      }
    }
    if (header.kind == FrameKind::kAckOnly) return false;
    ack_owed_ = true;  // every data frame is answered, so a lost ack is repaired by the next one
    if (header.seq == rx_expected_) {
      ++rx_expected_;
      ++counters_.delivered;
      return true;
    }
    // Behind: already delivered (our ack was lost). Ahead: a frame before it was lost.
    if (static_cast<int16_t>(header.seq - rx_expected_) < 0) ++counters_.duplicates;
    else ++counters_.out_of_order;
    return false;
  }

  // The sequence number the next in-order data frame must carry.
  uint16_t expected_seq() const { return rx_expected_; }
  // A receiver with memory to spare may keep data frames that arrived ahead of a gap. Once the
  // gap is filled and expected_seq() is a kept frame's number, this hands that frame up: it is
  // counted delivered and acknowledged as if it had just arrived.
  void deliver_kept() {
    ++rx_expected_;
    ++counters_.delivered;
    ack_owed_ = true;
  }

  // The next frame to put on the wire, if any is due: a retransmission (all unacknowledged frames
  // from the oldest, once its timer has run out), then new frames, then an ack-only frame when an
  // acknowledgement is owed. The caller transmits `wire` completely before asking again.
  bool next_frame(uint64_t now_us, uint8_t* wire, size_t capacity, size_t* wire_size) {
    if (count_ > 0 && !resending_) {
      const Slot& oldest = slots_[index(oldest_)];
      if (oldest.sent && now_us - oldest.sent_us >= timeout_us_) {
        resending_ = true;
        resend_next_ = oldest_;
        // No answer in time: wait twice as long for the next one (RFC 6298, 5.5).
        const uint64_t doubled = 2ull * timeout_us_;
        const uint64_t most = static_cast<uint64_t>(kMaxTimeoutFactor) * retransmit_us_;
        timeout_us_ = static_cast<uint32_t>(doubled < most ? doubled : most);
      }
    }
    if (resending_) {
      if (in_window(resend_next_) && slots_[index(resend_next_)].sent) {
        Slot& slot = slots_[index(resend_next_)];
        if (!encode_data(slot, wire, capacity, wire_size)) return false;
        ++counters_.retransmitted;
        slot.sent_us = now_us;
        slot.resent = true;
        ++resend_next_;
        return true;
      }
      resending_ = false;
    }
    for (uint16_t seq = oldest_; in_window(seq); ++seq) {
      Slot& slot = slots_[index(seq)];
      if (slot.sent) continue;
      if (!encode_data(slot, wire, capacity, wire_size)) return false;
      ++counters_.sent;
      slot.sent = true;
      slot.sent_us = now_us;
      return true;
    }
    if (!ack_owed_) return false;
    FrameHeader header;
    header.kind = FrameKind::kAckOnly;
    header.ack = static_cast<uint16_t>(rx_expected_ - 1);
    if (frame_encode(header, nullptr, 0, wire, capacity, wire_size) != Status::kOk) return false;
    ack_owed_ = false;
    ++counters_.acks_sent;
    return true;
  }

  // When next_frame() may next have something without new input: the oldest frame's timer. A
  // frame not sent yet waits for the wire, not for a time (`never`).
  uint64_t next_deadline_us(uint64_t never) const {
    if (count_ == 0) return never;
    const Slot& oldest = slots_[index(oldest_)];
    return oldest.sent ? oldest.sent_us + timeout_us_ : never;
  }

 private:
  struct Slot {
    uint8_t payload[kSlotPayload];
    uint16_t size = 0;  // <= kSlotPayload; 16 bits keep a slot to its payload plus 16 bytes
    uint16_t seq = 0;
    bool sent = false;
    bool resent = false;  // sent more than once: its ack cannot tell which copy it answers
    bool sync = false;  // sent as kSync: the session's first frame
    uint64_t sent_us = 0;
  };

  void start_session(uint16_t session_id) {
    session_ = session_id;
    next_seq_ = oldest_ = rx_expected_ = session_id;
  }
  static size_t index(uint16_t seq) { return seq % kWindow; }
  // seq is queued and not yet acknowledged.
  bool in_window(uint16_t seq) const {
    const int16_t from_oldest = static_cast<int16_t>(seq - oldest_);
    return from_oldest >= 0 && static_cast<size_t>(from_oldest) < count_;
  }
  bool encode_data(const Slot& slot, uint8_t* wire, size_t capacity, size_t* wire_size) {
    FrameHeader header;
    header.kind = slot.sync ? FrameKind::kSync : FrameKind::kData;
    header.seq = slot.seq;
    header.ack = slot.sync ? session_ : static_cast<uint16_t>(rx_expected_ - 1);
    if (frame_encode(header, slot.payload, slot.size, wire, capacity, wire_size) != Status::kOk) return false;
    if (!slot.sync) ack_owed_ = false;  // the frame carries the ack (a sync frame carries the session)
    return true;
  }

  // Frees every frame up to and including `ack` (cumulative); acks outside the window are stale.
  // True when it freed something.
  bool acknowledge(uint16_t ack, uint64_t now_us) {
    const int16_t ahead = static_cast<int16_t>(ack - oldest_);
    if (ahead < 0 || static_cast<size_t>(ahead) >= count_) return false;
    duplicate_acks_ = 0;
    const Slot& newest = slots_[index(ack)];
    if (newest.sent && !newest.resent && now_us >= newest.sent_us) measure(now_us - newest.sent_us);
    const uint16_t freed = static_cast<uint16_t>(ahead + 1);
    oldest_ = static_cast<uint16_t>(oldest_ + freed);
    count_ -= freed;
    if (resending_ && static_cast<int16_t>(resend_next_ - oldest_) < 0) resend_next_ = oldest_;
    return true;
  }

  // One round-trip sample (Karn: only frames sent once): the smoothed round trip and its mean
  // deviation, in integers (RFC 6298, 2.2-2.3), and the timeout from them.
  void measure(uint64_t sample_us) {
    // Samples beyond 268 s are cut there, so 7 * srtt and 4 * rttvar stay within 32 bits.
    constexpr uint64_t kLongest = 1u << 28;
    const int32_t r = static_cast<int32_t>(sample_us < kLongest ? sample_us : kLongest);
    if (srtt_us_ == 0 && rttvar_us_ == 0) {
      srtt_us_ = r;
      rttvar_us_ = r / 2;
    } else {
      const int32_t deviation = srtt_us_ > r ? srtt_us_ - r : r - srtt_us_;
      rttvar_us_ = (3 * rttvar_us_ + deviation) / 4;
      srtt_us_ = (7 * srtt_us_ + r) / 8;
    }
    const int64_t timeout = static_cast<int64_t>(srtt_us_) + 4 * static_cast<int64_t>(rttvar_us_);
    const int64_t least = retransmit_us_;
    const int64_t most = static_cast<int64_t>(kMaxTimeoutFactor) * retransmit_us_;
    timeout_us_ = static_cast<uint32_t>(timeout < least ? least : timeout > most ? most : timeout);
  }

  Slot slots_[kWindow];
  uint32_t retransmit_us_;
  uint32_t timeout_us_;       // the retransmission timeout in use
  int32_t srtt_us_ = 0;       // smoothed round trip (0 with rttvar_us_ 0: none measured yet)
  int32_t rttvar_us_ = 0;     // its mean deviation
  uint16_t next_seq_ = 1;     // seq of the next new frame
  uint16_t oldest_ = 1;       // seq of the oldest unacknowledged frame
  size_t count_ = 0;          // frames in the window
  uint16_t rx_expected_ = 1;  // the seq we deliver next
  bool ack_owed_ = false;
  uint16_t session_ = 0;      // the current session's id (0: none yet)
  bool restarted_ = false;
  int duplicate_acks_ = 0;    // ack-only frames in a row that freed nothing
  bool resending_ = false;    // going back over the window after a timeout
  uint16_t resend_next_ = 0;  // the next seq to resend while resending_
  LinkCounters counters_{};
};

}  // namespace dg
