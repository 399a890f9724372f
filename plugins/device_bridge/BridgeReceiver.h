#pragma once
// Takes what the other side sent since the last tick and keeps the newest
// valid packet, counting everything else by what was wrong with it: a
// foreign sender, a malformed packet (by reason), a stale or repeated
// sequence, packets lost in between (sequence gaps), packets superseded by a
// newer one in the same tick, and ticks that found more than it reads at
// once (a flood). Allocation-free: it runs in the haptic loop.
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
  uint64_t received = 0;    // valid new packets taken
  uint64_t foreign = 0;     // from a sender that is not the peer
  uint64_t wrongSize = 0;   // malformed, by reason (trephine_bridge_status)
  uint64_t badMagic = 0;
  uint64_t badVersion = 0;
  uint64_t badKind = 0;
  uint64_t badValues = 0;   // not finite, out of range, not a unit quaternion, reserved bits set
  uint64_t stale = 0;       // a sequence not newer than the last taken (repeated, reordered)
  uint64_t lost = 0;        // sequences never taken between two packets taken (lost or reordered)
  uint64_t superseded = 0;  // valid, but a newer one came in the same tick
  uint64_t floods = 0;      // ticks that left packets waiting

  uint64_t malformed() const { return wrongSize + badMagic + badVersion + badKind + badValues; }
  void count(trephine_bridge_status status);
  // Adds them to a component's summary entry, each name after `prefix`.
  void report(std::vector<Counter>& counters, const char* prefix) const;
};

template <class Packet>
class BridgeReceiver {
 public:
  using Decoder = trephine_bridge_status (*)(const unsigned char*, size_t, Packet*);
  explicit BridgeReceiver(Decoder decode) : m_decode(decode) {}

  // The newest valid packet since the last call, if any; `from`: its sender.
  std::optional<Packet> takeNewest(BridgeTransport& transport, trephine_bridge_address* from = nullptr) {
    bool more = false;
    const size_t n = transport.receive(m_buffer, more);
    if (more) ++m_counters.floods;
    std::optional<Packet> newest;
    uint64_t superseded = 0;  // newer than the last taken, older than the newest: not lost
    for (size_t i = 0; i < n; ++i) {
      const BridgeDatagram& d = m_buffer[i];
      if (!d.fromPeer) {
        ++m_counters.foreign;
        continue;
      }
      Packet packet;
      const trephine_bridge_status status =
          d.size > d.bytes.size() ? TREPHINE_BRIDGE_WRONG_SIZE : m_decode(d.bytes.data(), d.size, &packet);
      if (status != TREPHINE_BRIDGE_OK) {
        m_counters.count(status);
        continue;
      }
      const uint64_t last = newest ? newest->sequence : m_lastSequence;
      if ((newest || m_hasLast) && !trephine_bridge_is_newer(last, packet.sequence)) {
        ++m_counters.stale;
        continue;
      }
      if (newest) ++superseded;
      newest = packet;
      if (from) *from = d.from;
    }
    if (newest) {
      // A reordered packet counted stale above also lies in the gap: the
      // count is of sequences this side never took.
      if (m_hasLast) m_counters.lost += newest->sequence - m_lastSequence - 1 - superseded;
      m_counters.superseded += superseded;
      m_hasLast = true;
      m_lastSequence = newest->sequence;
      ++m_counters.received;
    }
    return newest;
  }

  const ReceiveCounters& counters() const { return m_counters; }

 private:
  Decoder m_decode;
  std::array<BridgeDatagram, 64> m_buffer{};  // at most this many packets a tick
  ReceiveCounters m_counters;
  uint64_t m_lastSequence = 0;
  bool m_hasLast = false;
};

}  // namespace trephine::device_bridge
