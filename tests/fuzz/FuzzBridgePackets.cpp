// libFuzzer target: arbitrary bytes as a device bridge packet (what a device
// program sends over shared memory or UDP, and what comes back). Any crash,
// sanitizer report or hang is a decoder bug. A packet the decoder accepts is
// valid (finite, in range, a unit quaternion) and encodes back to the same
// bytes; a refused one leaves the output untouched.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "trephine_bridge.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  trephine_bridge_pose pose;
  std::memset(&pose, 0xAB, sizeof pose);
  const trephine_bridge_pose untouched = pose;
  if (trephine_bridge_decode_pose(data, size, &pose) == TREPHINE_BRIDGE_OK) {
    double norm = 0;
    for (const double q : pose.orientation_wxyz) norm += q * q;
    if (!(std::abs(std::sqrt(norm) - 1) <= TREPHINE_BRIDGE_UNIT_TOLERANCE)) __builtin_trap();
    for (const double p : pose.position_mm)
      if (!(std::abs(p) <= TREPHINE_BRIDGE_MAX_POSITION_MM)) __builtin_trap();
    unsigned char again[TREPHINE_BRIDGE_POSE_SIZE];
    if (trephine_bridge_encode_pose(&pose, again) != TREPHINE_BRIDGE_OK) __builtin_trap();
    if (size != sizeof again || std::memcmp(again, data, size) != 0) __builtin_trap();
  } else if (std::memcmp(&pose, &untouched, sizeof pose) != 0) {
    __builtin_trap();
  }
  trephine_bridge_force force;
  if (trephine_bridge_decode_force(data, size, &force) == TREPHINE_BRIDGE_OK) {
    for (const double f : force.force_n)
      if (!(std::abs(f) <= TREPHINE_BRIDGE_MAX_FORCE_N)) __builtin_trap();
    unsigned char again[TREPHINE_BRIDGE_FORCE_SIZE];
    if (trephine_bridge_encode_force(&force, again) != TREPHINE_BRIDGE_OK) __builtin_trap();
    if (size != sizeof again || std::memcmp(again, data, size) != 0) __builtin_trap();
  }
  return 0;
}
