#pragma once
// The fields both ends of the bridge declare (how the packets travel, and
// the safety each side keeps), and opening the transport they describe.
#include <memory>
#include <string>

#include "framework/core/Field.h"
#include "plugins/device_bridge/BridgeTransport.h"

namespace trephine::device_bridge {

struct BridgeConnectionFields {
  BridgeConnectionFields(FieldOwner* owner, BridgeSide side);

  // Checks the fields together; returns the problem, or "" (call in init).
  std::string problem() const;
  // Opens the transport; throws std::runtime_error saying what failed.
  std::unique_ptr<BridgeTransport> open() const;

  BridgeSide side;
  EnumField transport;
  Field<std::string> channel;
  Field<std::string> address;
  Field<std::string> peer;
  Field<double> timeout;
  Field<double> rampTime;
  Field<double> maxForce;
};

}  // namespace trephine::device_bridge
