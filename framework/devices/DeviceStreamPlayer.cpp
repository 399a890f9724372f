#include "framework/devices/DeviceStreamPlayer.h"

namespace trephine {

DeviceSample DeviceStreamPlayer::at(double t) {
  if (m_cursor >= m_samples.size() || m_samples[m_cursor].t > t) m_cursor = 0;
  while (m_cursor + 1 < m_samples.size() && m_samples[m_cursor + 1].t <= t) ++m_cursor;
  DeviceSample sample = m_samples[m_cursor];
  const bool between = t > sample.t && m_cursor + 1 < m_samples.size();
  if (between) {
    const DeviceSample& next = m_samples[m_cursor + 1];
    const double u = (t - sample.t) / (next.t - sample.t);
    // A recorded bad sample (NaN, Inf) is kept as it was, never blended into its neighbour.
    if (next.position.allFinite() && sample.position.allFinite())
      sample.position += u * (next.position - sample.position);
    if (next.orientation.coeffs().allFinite() && sample.orientation.coeffs().allFinite())
      sample.orientation = sample.orientation.normalized().slerp(u, next.orientation.normalized());
  }
  return sample;
}

}  // namespace trephine
