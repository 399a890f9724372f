#pragma once
// Decides whether a raw device sample can be trusted. Pure and allocation-free.
#include "framework/devices/DeviceSample.h"

namespace trephine {

enum class SampleVerdict { Accepted, NonFinite, Jump };

class DevicePoseFilter {
 public:
  // `maxSpeed` in mm/s. A sample is a jump when it lies farther from the last
  // accepted one than maxSpeed allows in the time between them (at least one
  // period), so after a gap of n rejected frames the hand may have moved n
  // frames' worth. Orientation must be a usable rotation (norm within [0.5, 2]).
  SampleVerdict check(const DeviceSample& sample, double maxSpeed, double period) const;
  void accept(const DeviceSample& sample) {
    m_last = sample;
    m_hasLast = true;
  }
  void forget() { m_hasLast = false; }
  bool hasLast() const { return m_hasLast; }
  const DeviceSample& last() const { return m_last; }

 private:
  DeviceSample m_last;
  bool m_hasLast = false;
};

}  // namespace trephine
