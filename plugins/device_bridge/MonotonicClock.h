#pragma once
// The clock both ends of a bridge on one machine read (CLOCK_MONOTONIC, ns),
// so a device program's times and the simulation's compare directly.
#include <cstdint>
#include <ctime>

namespace trephine::device_bridge {

inline uint64_t monotonicNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1000000000ull + static_cast<uint64_t>(ts.tv_nsec);
}

}  // namespace trephine::device_bridge
