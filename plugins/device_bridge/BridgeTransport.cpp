#include "plugins/device_bridge/BridgeTransport.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "trephine_bridge.h"
#include "trephine_bridge_shm.h"

namespace trephine::device_bridge {
namespace {

class SharedMemoryTransport final : public BridgeTransport {
 public:
  SharedMemoryTransport(std::string name, BridgeSide side) : m_name(std::move(name)), m_side(side) {
    int error = 0;
    m_shm = trephine_bridge_shm_open(m_name.c_str(), 1, &error);
    if (!m_shm)
      throw std::runtime_error(
          "cannot open the shared memory object " + m_name + ": " +
          (error == EPROTO ? std::string("it holds something other than a device bridge of this version (remove it: "
                                         "rm /dev/shm" + m_name + ")")
           : error == EPERM
               ? std::string("it belongs to another user or others may read or write it, and whoever can write it "
                             "drives the device (remove it, rm /dev/shm" + m_name +
                             ", and let this side make it owner-only)")
               : std::string(std::strerror(error))));
    // One simulation a channel: a second would answer the same device.
    if (m_side == BridgeSide::Simulation) {
      if (const long holder = trephine_bridge_shm_claim(m_shm, static_cast<long>(getpid()))) {
        trephine_bridge_shm_close(m_shm, m_name.c_str(), 0);
        throw std::runtime_error("the shared memory object " + m_name + " is in use by another simulation (process " +
                                 std::to_string(holder) + "): give this one another channel");
      }
    }
    // Another process may truncate the object under this one: the mapping is
    // checked once a tick, and a fault in the moment between is caught.
    if (trephine_bridge_shm_guard_truncation(m_shm) != 0) {
      if (m_side == BridgeSide::Simulation) trephine_bridge_shm_release(m_shm, static_cast<long>(getpid()));
      trephine_bridge_shm_close(m_shm, m_name.c_str(), 0);
      throw std::runtime_error("cannot guard the shared memory object " + m_name +
                               " against truncation (more than 8 bridges in one process, or SIGBUS taken)");
    }
    // What the other side wrote before this side opened it (a device program
    // of an earlier run, now gone) is not news.
    m_lastSeen = incomingWrites();
  }
  ~SharedMemoryTransport() override {
    if (m_side == BridgeSide::Simulation) trephine_bridge_shm_release(m_shm, static_cast<long>(getpid()));
    trephine_bridge_shm_close(m_shm, m_name.c_str(), 0);
  }

  size_t receive(std::span<BridgeDatagram> into, bool& more) override {
    more = false;
    if (!trephine_bridge_shm_intact(m_shm)) return 0;
    const uint64_t writes = incomingWrites();
    if (into.empty() || writes == m_lastSeen) return 0;
    BridgeDatagram& d = into[0];
    d.fromPeer = true;
    const bool whole = m_side == BridgeSide::Simulation ? trephine_bridge_shm_read_pose(m_shm, d.bytes.data())
                                                        : trephine_bridge_shm_read_force(m_shm, d.bytes.data());
    if (!whole) return 0;  // a write under way: the next tick has it
    m_lastSeen = writes;
    d.size = m_side == BridgeSide::Simulation ? TREPHINE_BRIDGE_POSE_SIZE : TREPHINE_BRIDGE_FORCE_SIZE;
    return 1;
  }
  bool waiting() const override { return incomingWrites() != m_lastSeen; }
  bool send(const unsigned char* packet, size_t size) override {
    if (!trephine_bridge_shm_intact(m_shm)) return false;
    if (m_side == BridgeSide::Simulation) {
      if (size != TREPHINE_BRIDGE_FORCE_SIZE) return false;
      trephine_bridge_shm_write_force(m_shm, packet);
    } else {
      if (size != TREPHINE_BRIDGE_POSE_SIZE) return false;
      trephine_bridge_shm_write_pose(m_shm, packet);
    }
    return true;
  }
  std::string describe() const override { return "shared memory " + m_name; }
  const char* failure() override {
    return trephine_bridge_shm_intact(m_shm) ? nullptr
                                              : "the shared memory object was truncated under the bridge "
                                                "(by another process): the device can no longer be heard";
  }

 private:
  uint64_t incomingWrites() const {
    return m_side == BridgeSide::Simulation ? trephine_bridge_shm_pose_writes(m_shm)
                                            : trephine_bridge_shm_force_writes(m_shm);
  }
  std::string m_name;
  BridgeSide m_side;
  trephine_bridge_shm* m_shm = nullptr;
  uint64_t m_lastSeen = 0;
};

class UdpTransport final : public BridgeTransport {
 public:
  UdpTransport(const trephine_bridge_address& local, const std::optional<trephine_bridge_address>& peer)
      : m_peer(peer), m_fixed(peer.has_value()) {
    int error = 0;
    m_udp = trephine_bridge_udp_open(&local, &error);
    if (!m_udp)
      throw std::runtime_error("cannot bind UDP " + formatAddress(local) + ": " + std::strerror(error));
  }
  ~UdpTransport() override { trephine_bridge_udp_close(m_udp); }

  size_t receive(std::span<BridgeDatagram> into, bool& more) override {
    more = false;
    size_t n = 0;
    while (n < into.size()) {
      BridgeDatagram& d = into[n];
      const long size = trephine_bridge_udp_receive(m_udp, d.bytes.data(), d.bytes.size(), &d.from);
      if (size < 0) return n;
      d.size = static_cast<size_t>(size);
      d.fromPeer = !m_peer || trephine_bridge_address_equal(&*m_peer, &d.from);
      d.mayBecomePeer = !m_fixed;
      ++n;
    }
    more = trephine_bridge_udp_wait(m_udp, 0) != 0;
    return n;
  }
  bool waiting() const override { return trephine_bridge_udp_wait(m_udp, 0) != 0; }
  bool send(const unsigned char* packet, size_t size) override {
    return m_peer && trephine_bridge_udp_send(m_udp, &*m_peer, packet, size) == 0;
  }
  void followPeer(const trephine_bridge_address& peer) override {
    if (!m_fixed) m_peer = peer;
  }
  bool hasPeer() const override { return m_peer.has_value(); }
  std::string describe() const override {
    return "UDP " + formatAddress(trephine_bridge_udp_local(m_udp)) +
           (m_peer ? " with " + formatAddress(*m_peer) : std::string());
  }

 private:
  trephine_bridge_udp* m_udp = nullptr;
  std::optional<trephine_bridge_address> m_peer;
  bool m_fixed = false;  // the peer was given: only its packets are heard
};

}  // namespace

std::unique_ptr<BridgeTransport> openSharedMemory(const std::string& name, BridgeSide side) {
  return std::make_unique<SharedMemoryTransport>(name, side);
}

std::unique_ptr<BridgeTransport> openUdp(const trephine_bridge_address& local,
                                         const std::optional<trephine_bridge_address>& peer, BridgeSide side) {
  (void)side;  // the same on both sides: datagrams carry their own kind
  return std::make_unique<UdpTransport>(local, peer);
}

std::optional<trephine_bridge_address> parseHostPort(const std::string& text, std::string& error, bool anyPort) {
  const size_t colon = text.rfind(':');
  const std::string host = colon == std::string::npos ? std::string() : text.substr(0, colon);
  const std::string port = colon == std::string::npos ? text : text.substr(colon + 1);
  char* end = nullptr;
  errno = 0;
  const long value = port.empty() ? -1 : std::strtol(port.c_str(), &end, 10);
  if (value < (anyPort ? 0 : 1) || value > 65535 || errno || *end) {
    error = "'" + text + "' is not HOST:PORT (a dotted IPv4 address and a port from " + (anyPort ? "0" : "1") +
            " to 65535)";
    return std::nullopt;
  }
  trephine_bridge_address address{};
  if (trephine_bridge_address_parse(host.c_str(), static_cast<uint16_t>(value), &address) != 0) {
    error = "'" + host + "' is not a dotted IPv4 address (names are not looked up)";
    return std::nullopt;
  }
  return address;
}

std::string formatAddress(const trephine_bridge_address& a) {
  return std::to_string(a.ipv4 >> 24) + "." + std::to_string((a.ipv4 >> 16) & 255u) + "." +
         std::to_string((a.ipv4 >> 8) & 255u) + "." + std::to_string(a.ipv4 & 255u) + ":" + std::to_string(a.port);
}

}  // namespace trephine::device_bridge
