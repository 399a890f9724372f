#include "plugins/haptics/ReplayDevice.h"

#include <cmath>

#include "framework/core/Lifecycle.h"
#include "framework/devices/DeviceStream.h"

namespace trephine::haptics {

void ReplayDevice::init(InitContext& context) {
  DeviceStreamReadResult read = readDeviceStream(d_file.path());
  if (!read.error.empty()) {
    context.error(d_file, read.error);
    return;
  }
  m_samples = std::move(read.samples);
  for (DeviceSample& s : m_samples) s.position += d_offset.value();
}

void ReplayDevice::prepare(const RunPlan& plan) {
  HapticDevice::prepare(plan);
  m_cursor = 0;
}

double ReplayDevice::preferredDuration() const {
  if (m_samples.empty()) return 0;
  return m_samples.back().t + 1.0 / rateHz();
}

DeviceSample ReplayDevice::readSample(double t) {
  const double first = m_samples.front().t, last = m_samples.back().t;
  if (d_loop.value() && t > last) {
    const double span = last - first + 1.0 / rateHz();
    t = first + std::fmod(t - first, span);
  }
  // Times only move forward within one pass, so the cursor search is amortised O(1).
  if (m_cursor >= m_samples.size() || m_samples[m_cursor].t > t) m_cursor = 0;
  while (m_cursor + 1 < m_samples.size() && m_samples[m_cursor + 1].t <= t) ++m_cursor;
  DeviceSample sample = m_samples[m_cursor];
  const bool between = t > sample.t && m_cursor + 1 < m_samples.size();
  if (between) {
    const DeviceSample& next = m_samples[m_cursor + 1];
    const double u = (t - sample.t) / (next.t - sample.t);
    if (next.position.allFinite() && sample.position.allFinite()) sample.position += u * (next.position - sample.position);
    if (next.orientation.coeffs().allFinite() && sample.orientation.coeffs().allFinite())
      sample.orientation = sample.orientation.normalized().slerp(u, next.orientation.normalized());
  }
  sample.t = t;
  return sample;
}

}  // namespace trephine::haptics
