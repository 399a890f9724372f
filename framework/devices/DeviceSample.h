#pragma once
#include <cstdint>

#include "framework/math/Math.h"

namespace trephine {

// One raw device reading, as in a device stream file: t,x,y,z,qw,qx,qy,qz,buttons (s, mm).
struct DeviceSample {
  double t = 0;
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
  uint32_t buttons = 0;
};

}  // namespace trephine
