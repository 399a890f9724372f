#include "plugins/device_bridge/BridgeConnection.h"

#include <climits>
#include <stdexcept>

namespace trephine::device_bridge {

namespace {
constexpr const char* kDefaultChannel = "/trephine-bridge";
constexpr const char* kSimulationAddress = "127.0.0.1:27200";
}  // namespace

BridgeConnectionFields::BridgeConnectionFields(FieldOwner* owner, BridgeSide side_)
    : side(side_),
      transport{owner,
                "transport",
                {"shm", "udp"},
                "shm",
                {.help = "How packets travel: shared memory (this machine), or UDP datagrams (another machine, or "
                         "this one)"}},
      channel{owner,
              "channel",
              kDefaultChannel,
              {.help = "The shared memory object (transport shm): a leading slash and no other; both sides name "
                       "the same"}},
      address{owner,
              "address",
              side_ == BridgeSide::Simulation ? kSimulationAddress : "127.0.0.1:0",
              {.help = side_ == BridgeSide::Simulation
                           ? "Where this side listens for the device's poses (transport udp): HOST:PORT, a dotted "
                             "IPv4 address; 127.0.0.1 unless another is asked for"
                           : "Where this side binds (transport udp): HOST:PORT, port 0 for any free one"}},
      peer{owner,
           "peer",
           side_ == BridgeSide::Simulation ? "" : kSimulationAddress,
           {.help = side_ == BridgeSide::Simulation
                        ? "The device program's HOST:PORT (transport udp): only it is heard. Empty: the first "
                          "sender of a valid pose, kept for the run"
                        : "The simulation's HOST:PORT (transport udp): where poses go, and the only sender heard"}},
      timeout{owner,
              "timeout",
              0.02,
              {.help = side_ == BridgeSide::Simulation
                           ? "The device quiet (no new valid pose) for longer than this: the force sent to it "
                             "ramps to zero and an event is logged"
                           : "The simulation quiet (no new valid force) for longer than this: the force commanded "
                             "ramps to zero by itself",
               .unit = "s",
               .min = 0.0,
               .max = 10.0,
               .minExclusive = true}},
      rampTime{owner,
               "rampTime",
               0.02,
               {.help = "The force's ramp to zero after a timeout, and back once heard again (0: cut in one step)",
                .unit = "s",
                .min = 0.0,
                .max = 10.0}},
      maxForce{owner,
               "maxForce",
               3.3,
               {.help = "Largest force the device is commanded; a larger one is scaled down, its direction kept "
                        "(the Phantom Omni's datasheet: 3.3 N)",
                .unit = "N",
                .min = 0.0,
                .max = 1000.0}} {}

std::string BridgeConnectionFields::problem() const {
  std::string error;
  // Every field is checked whatever the transport, so a mistake shows before the transport is switched.
  const std::string& name = channel.value();
  if (name.size() < 2 || name[0] != '/' || name.find('/', 1) != std::string::npos || name.size() > NAME_MAX)
    return "channel '" + name + "' is not a shared memory name: a leading slash, then a name without one";
  if (!parseHostPort(address.value(), error, side == BridgeSide::Device)) return "address: " + error;
  if (!peer.value().empty() && !parseHostPort(peer.value(), error)) return "peer: " + error;
  if (transport.is("udp") && side == BridgeSide::Device && peer.value().empty())
    return "peer: the simulation's HOST:PORT is needed";
  return {};
}

std::unique_ptr<BridgeTransport> BridgeConnectionFields::open() const {
  if (transport.is("shm")) return openSharedMemory(channel.value(), side);
  std::string error;
  const auto local = parseHostPort(address.value(), error, side == BridgeSide::Device);
  if (!local) throw std::runtime_error("address: " + error);
  std::optional<trephine_bridge_address> other;
  if (!peer.value().empty()) {
    other = parseHostPort(peer.value(), error);
    if (!other) throw std::runtime_error("peer: " + error);
  }
  return openUdp(*local, other, side);
}

}  // namespace trephine::device_bridge
