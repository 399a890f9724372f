#include "framework/devices/DevicePoseFilter.h"

#include <algorithm>
#include <cmath>

namespace trephine {

SampleVerdict DevicePoseFilter::check(const DeviceSample& sample, double maxSpeed, double period) const {
  if (!std::isfinite(sample.t) || !sample.position.allFinite() || !sample.orientation.coeffs().allFinite())
    return SampleVerdict::NonFinite;
  const double norm = sample.orientation.norm();
  if (norm < 0.5 || norm > 2.0) return SampleVerdict::NonFinite;
  if (m_hasLast) {
    const double elapsed = std::max(sample.t - m_last.t, period);
    if ((sample.position - m_last.position).norm() > maxSpeed * elapsed) return SampleVerdict::Jump;
  }
  return SampleVerdict::Accepted;
}

}  // namespace trephine
