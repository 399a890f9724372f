#pragma once
// Takes what the other side sent and keeps the newest packet to take,
// counting everything else by what was wrong with it: a foreign sender (not
// the one heard, while it is heard), a
// malformed packet (by reason), a stale or repeated sequence, one further
// ahead than the time since the last explains, another session while the
// one taken is still heard (trephine_bridge_stream), packets lost in between
// (sequence gaps), packets superseded by a newer one before they were taken,
// and reads that left packets waiting (a flood). Each poll reads at most one
// batch: the work a tick does for junk is bounded, and junk never counts as
// input. Allocation-free: it runs in the haptic loop.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "framework/core/Component.h"
#include "plugins/device_bridge/BridgeTransport.h"
#include "trephine_bridge.h"

namespace trephine::device_bridge {

struct ReceiveCounters {
  uint64_t received = 0;      // valid new packets taken
  uint64_t foreign = 0;       // from a sender that is not the peer
  uint64_t wrongSize = 0;     // malformed, by reason (trephine_bridge_status)
  uint64_t badMagic = 0;
  uint64_t badVersion = 0;
  uint64_t badKind = 0;
  uint64_t badValues = 0;     // not finite, out of range, not a unit quaternion, reserved bits set, no session
  uint64_t stale = 0;         // a sequence not newer than the last taken (repeated, reordered)
  uint64_t tooFarAhead = 0;   // a sequence further ahead than the time since the last taken explains
  uint64_t otherSession = 0;  // another sender's session while the one taken is still heard
  uint64_t lost = 0;          // sequences never taken between two packets taken (lost or reordered)
  uint64_t superseded = 0;    // valid, but a newer one came before it was taken
  uint64_t floods = 0;        // reads that left packets waiting
  uint64_t sessions = 0;      // the other side's sessions taken (a restart of it takes another)

  uint64_t malformed() const { return wrongSize + badMagic + badVersion + badKind + badValues; }
  void count(trephine_bridge_status status);
  // Adds them to a component's summary entry, each name after `prefix`.
  void report(std::vector<Counter>& counters, const char* prefix) const;
};

template <class Packet>
class BridgeReceiver {
 public:
  using Decoder = trephine_bridge_status (*)(const unsigned char*, size_t, Packet*);
  explicit BridgeReceiver(Decoder decode) : m_decode(decode) { trephine_bridge_stream_init(&m_stream, 0.05, 0); }

  // Forgets every session; `quietS`: how long the session taken must be
  // quiet before another is taken (the receiver's watchdog time).
  void reset(double quietS) {
    trephine_bridge_stream_init(&m_stream, quietS, 0);
    m_counters = {};
    m_pending.reset();
    m_restarted = false;
  }

  // Reads one batch of what waits at `nowNs`, keeping the newest packet to
  // take. Returns whether one is kept (input for the next frame).
  bool poll(BridgeTransport& transport, uint64_t nowNs) {
    if (!transport.waiting()) return m_pending.has_value();
    bool more = false;
    const size_t n = transport.receive(m_buffer, more);
    if (more) ++m_counters.floods;
    for (size_t i = 0; i < n; ++i) judge(m_buffer[i], nowNs);
    return m_pending.has_value();
  }

  // The packet kept since the last take, once; `from`: its sender.
  std::optional<Packet> take(trephine_bridge_address* from = nullptr) {
    if (!m_pending) return std::nullopt;
    if (from) *from = m_pendingFrom;
    ++m_counters.received;
    std::optional<Packet> packet = m_pending;
    m_pending.reset();
    return packet;
  }

  // poll, then take.
  std::optional<Packet> takeNewest(BridgeTransport& transport, uint64_t nowNs, trephine_bridge_address* from = nullptr) {
    poll(transport, nowNs);
    return take(from);
  }

  // Whether a session after the first was taken since the last call: the
  // other side restarted (its packets are taken from its new start).
  bool takeRestart() {
    const bool restarted = m_restarted;
    m_restarted = false;
    return restarted;
  }

  const trephine_bridge_stream& stream() const { return m_stream; }
  const ReceiveCounters& counters() const { return m_counters; }

 private:
  void judge(const BridgeDatagram& d, uint64_t nowNs) {
    // Another sender than the one heard: foreign, unless the peer may change
    // and the session heard went quiet (a device program started again
    // sends from a new port).
    const bool quiet = m_stream.session == 0 || nowNs - m_stream.taken_ns >= m_stream.quiet_ns;
    if (!d.fromPeer && !(d.mayBecomePeer && quiet)) {
      ++m_counters.foreign;
      return;
    }
    Packet packet;
    const trephine_bridge_status status =
        d.size > d.bytes.size() ? TREPHINE_BRIDGE_WRONG_SIZE : m_decode(d.bytes.data(), d.size, &packet);
    if (status != TREPHINE_BRIDGE_OK) {
      m_counters.count(status);
      return;
    }
    switch (trephine_bridge_stream_judge(&m_stream, packet.session, packet.sequence, nowNs)) {
      case TREPHINE_BRIDGE_STALE:
        ++m_counters.stale;
        return;
      case TREPHINE_BRIDGE_TOO_FAR_AHEAD:
        ++m_counters.tooFarAhead;
        return;
      case TREPHINE_BRIDGE_OTHER_SESSION:
        ++m_counters.otherSession;
        return;
      case TREPHINE_BRIDGE_TAKE:
        // A reordered packet counted stale later also lies in the gap: the
        // count is of sequences this side never took.
        m_counters.lost += packet.sequence - m_stream.sequence - 1;
        break;
      case TREPHINE_BRIDGE_NEW_SESSION:
        if (m_stream.session != 0) m_restarted = true;
        ++m_counters.sessions;
        break;
    }
    if (m_pending) ++m_counters.superseded;
    trephine_bridge_stream_take(&m_stream, packet.session, packet.sequence, nowNs);
    m_pending = packet;
    m_pendingFrom = d.from;
  }

  Decoder m_decode;
  std::array<BridgeDatagram, 64> m_buffer{};  // at most this many packets a poll
  ReceiveCounters m_counters;
  trephine_bridge_stream m_stream{};
  std::optional<Packet> m_pending;
  trephine_bridge_address m_pendingFrom{};
  bool m_restarted = false;
};

}  // namespace trephine::device_bridge
