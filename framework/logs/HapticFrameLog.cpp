#include "framework/logs/HapticFrameLog.h"

#include <algorithm>
#include <cmath>

namespace trephine {

namespace {
bool frameHasNaN(const HapticFrame& f) {
  return !f.device.allFinite() || !f.proxy.allFinite() || !f.force.allFinite() || !std::isfinite(f.penetration) ||
         !f.normal.allFinite();
}
}  // namespace

HapticStats HapticFrameLog::stats() const {
  HapticStats s;
  s.frames = m_size;
  s.droppedFrames = m_dropped;
  double forceSum = 0, penetrationSum = 0;
  std::vector<double> steps;
  steps.reserve(m_size);
  for (size_t i = 0; i < m_size; ++i) {
    const HapticFrame& f = m_frames[i];
    if (frameHasNaN(f)) {
      ++s.nanFrames;
      continue;  // a NaN frame has no meaningful magnitude; it is counted instead
    }
    const double force = f.force.norm();
    s.forceMax = std::max(s.forceMax, force);
    forceSum += force;
    if (f.contacts > 0) {
      ++s.contactFrames;
      s.penetrationMax = std::max(s.penetrationMax, f.penetration);
      penetrationSum += f.penetration;
    }
    if (f.proxyInside) ++s.proxyInsideFrames;
    if (i > 0 && m_frames[i - 1].force.allFinite()) {
      steps.push_back((f.force - m_frames[i - 1].force).norm());
    }
  }
  const size_t finite = m_size - s.nanFrames;
  if (finite > 0) s.forceMean = forceSum / static_cast<double>(finite);
  if (s.contactFrames > 0) s.penetrationMean = penetrationSum / static_cast<double>(s.contactFrames);
  if (!steps.empty()) {
    std::sort(steps.begin(), steps.end());
    s.forceStepMax = steps.back();
    // Nearest-rank percentile: the smallest value with at least 99% of steps at or below it.
    const size_t rank = static_cast<size_t>(std::ceil(0.99 * static_cast<double>(steps.size())));
    s.forceStepP99 = steps[std::max<size_t>(rank, 1) - 1];
  }
  return s;
}

}  // namespace trephine
