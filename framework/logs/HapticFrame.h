#pragma once
// One haptic frame as written to trace.csv (mm, N, s).
#include <cstdint>

#include "framework/math/Math.h"

namespace trephine {

struct HapticFrame {
  double t = 0;                // s, scheduled time of the frame
  Vec3 device = Vec3::Zero();  // mm, device (haptic interface point) position
  Vec3 proxy = Vec3::Zero();   // mm, displayed proxy position
  Vec3 force = Vec3::Zero();   // N, force sent to the device
  double penetration = 0;      // mm, depth used for the force
  Vec3 normal = Vec3::Zero();  // unit contact normal, zero without contact
  int32_t contacts = 0;        // number of contact points this frame
  bool proxyInside = false;    // displayed proxy overlaps the target
  // Extra trace columns (after the contract's columns):
  double rawPenetration = 0;  // mm, depth measured by the detection before the proxy rectified it
  int32_t primitives = 0;     // colliding primitives (voxels, tetrahedra) this frame
  int32_t removed = 0;        // primitives removed this frame (drilled voxels)
  // The target this frame's contact is with (its identity, for a study that
  // probes one target of several; not written to the trace); null when the
  // renderer does not say.
  const void* target = nullptr;
  const void* tool = nullptr;  // and the tool that touches it (the same)
};

}  // namespace trephine
