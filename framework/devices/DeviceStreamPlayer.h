#pragma once
// Plays a recorded device stream back: at a recorded time the recorded sample
// itself (so a run replayed at its own rate reproduces its input to the bit),
// between two samples a blend of them (linear position, spherical
// orientation), before the first the first and after the last the last.
// Used by ReplayDevice (a stream file as a device) and by a device whose
// input a study replaces with the reference run's (HapticDevice::replaceInput).
#include <vector>

#include "framework/devices/DeviceSample.h"

namespace trephine {

class DeviceStreamPlayer {
 public:
  DeviceStreamPlayer() = default;
  explicit DeviceStreamPlayer(std::vector<DeviceSample> samples) : m_samples(std::move(samples)) {}

  bool empty() const { return m_samples.empty(); }
  const std::vector<DeviceSample>& samples() const { return m_samples; }

  // The stream at time t (s), the sample's own t kept. Times that only move
  // forward cost O(1) amortised; a step back starts the search over. Does
  // not allocate. The stream must not be empty.
  DeviceSample at(double t);
  void rewind() { m_cursor = 0; }

 private:
  std::vector<DeviceSample> m_samples;
  size_t m_cursor = 0;
};

}  // namespace trephine
