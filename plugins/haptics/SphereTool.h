#pragma once
// The simplest tool: a sphere of `radius` whose centre follows a device.
#include "framework/devices/HapticDevice.h"

namespace trephine::haptics {

class SphereTool final : public Component {
 public:
  static constexpr std::string_view kTypeName = "SphereTool";

  double radius() const { return d_radius.value(); }
  HapticDevice& device() const { return *l_device; }
  // Centre of the sphere in the world (mm): the device pose applied to `offset`.
  Vec3 center() const {
    const Pose& X_WD = l_device->state().pose;
    return X_WD.position + X_WD.orientation * d_offset.value();
  }

 private:
  Link<HapticDevice> l_device{this, "device", {.help = "Device that moves the tool", .required = true}};
  Field<double> d_radius{
      this, "radius", 2.5, {.help = "Sphere radius", .unit = "mm", .min = 0.0, .minExclusive = true}};
  Field<Vec3> d_offset{this, "offset", Vec3::Zero(), {.help = "Sphere centre in the device frame", .unit = "mm"}};
};

}  // namespace trephine::haptics
