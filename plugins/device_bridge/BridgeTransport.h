#pragma once
// How the bridge's packets travel between the simulation and a device
// program: shared memory on one machine (the latest packet in a slot), or
// UDP datagrams (every packet, in order of arrival). Both sides of the
// bridge use the same transports; neither ever waits.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "trephine_bridge_udp.h"

namespace trephine::device_bridge {

enum class BridgeSide { Simulation, Device };

// One packet as it came, before decoding (so malformed ones can be counted).
struct BridgeDatagram {
  std::array<unsigned char, 128> bytes{};
  size_t size = 0;           // the datagram's whole size (larger than bytes when cut)
  bool fromPeer = true;      // sent by the peer (or by anyone while no peer is set)
  bool mayBecomePeer = false;  // another sender, who may become the peer (UDP without a fixed one)
  trephine_bridge_address from{};
};

class BridgeTransport {
 public:
  virtual ~BridgeTransport() = default;
  // The packets from the other side since the last call, at most
  // into.size() of them (shared memory: the latest one only). Returns how
  // many; sets `more` when more were waiting. Never waits.
  virtual size_t receive(std::span<BridgeDatagram> into, bool& more) = 0;
  // Whether a packet from the other side waits (one atomic load, or a poll).
  virtual bool waiting() const = 0;
  // Sends this side's packet; false when it was dropped (no peer yet, a full buffer).
  virtual bool send(const unsigned char* packet, size_t size) = 0;
  // UDP without a fixed peer: the sender of the packets taken (those of the
  // session taken, trephine_bridge_stream) is where this side's packets go,
  // so a device program started again (from another port) is answered
  // there once its earlier session went quiet. With a fixed peer, nothing.
  virtual void followPeer(const trephine_bridge_address& peer) { (void)peer; }
  virtual bool hasPeer() const { return true; }
  // Why the transport can no longer be used (the shared memory object was
  // truncated or removed under it), or null while it can.
  virtual const char* failure() { return nullptr; }
  // "shared memory /trephine-bridge", "UDP 127.0.0.1:27200".
  virtual std::string describe() const = 0;
};

// Opens (creating when absent) the shared memory object `name`. Throws
// std::runtime_error saying what failed and why. The simulation's side
// removes the name when it closes.
std::unique_ptr<BridgeTransport> openSharedMemory(const std::string& name, BridgeSide side);
// Binds `local`; `peer`: where to send and whom to hear (on the simulation's
// side it may be left unset: see followPeer). Throws std::runtime_error.
std::unique_ptr<BridgeTransport> openUdp(const trephine_bridge_address& local,
                                         const std::optional<trephine_bridge_address>& peer, BridgeSide side);

// "127.0.0.1:27200" or "27200" (host 127.0.0.1) into an address; nullopt
// with `error` set for anything else. Port 0 (any free one) only when
// `anyPort` allows it.
std::optional<trephine_bridge_address> parseHostPort(const std::string& text, std::string& error,
                                                     bool anyPort = false);
std::string formatAddress(const trephine_bridge_address& address);

}  // namespace trephine::device_bridge
