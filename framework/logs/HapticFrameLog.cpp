#include "framework/logs/HapticFrameLog.h"

#include <algorithm>
#include <cmath>
#include <deque>

namespace trephine {

namespace {

constexpr double kGenerationWindow = 0.1;  // s, window of max_generated_mJ_per_100ms
constexpr double kReversalForce = 0.5;     // N, below this a sign change is noise around zero, not a reversal

bool frameHasNaN(const HapticFrame& f) {
  return !f.device.allFinite() || !f.proxy.allFinite() || !f.force.allFinite() || !std::isfinite(f.penetration) ||
         !f.normal.allFinite();
}

// Nearest-rank percentile: the smallest value with at least q of the values at or below it.
double percentile(std::vector<double>& values, double q) {
  std::sort(values.begin(), values.end());
  const size_t rank = static_cast<size_t>(std::ceil(q * static_cast<double>(values.size())));
  return values[std::max<size_t>(rank, 1) - 1];
}

// Passivity observer: E after each frame, the force of frame k held while the
// device moved from x_k to x_{k+1}; with the device's damping b, also E_b.
// Pairs with a non-finite value add nothing.
void observePassivity(const HapticFrame* frames, size_t n, std::optional<double> deviceDamping, HapticStats& s) {
  if (n == 0) return;
  std::vector<double> energy(n, 0.0);  // mJ
  double withDevice = 0;               // mJ, E_b
  for (size_t k = 1; k < n; ++k) {
    const HapticFrame& a = frames[k - 1];
    const HapticFrame& b = frames[k];
    const bool finite = a.force.allFinite() && a.device.allFinite() && b.device.allFinite();
    const Vec3 dx = finite ? Vec3(b.device - a.device) : Vec3::Zero();  // mm
    energy[k] = energy[k - 1] - (finite ? a.force.dot(dx) : 0.0);
    if (deviceDamping) {
      const double dt = b.t - a.t;  // s
      withDevice += -(finite ? a.force.dot(dx) : 0.0) + (dt > 0 ? *deviceDamping * dx.squaredNorm() / dt : 0.0);
      s.minEnergyInWithDevice_mJ = std::min(s.minEnergyInWithDevice_mJ, withDevice);
    }
  }
  s.energyIn_mJ = energy.back();
  s.minEnergyIn_mJ = *std::min_element(energy.begin(), energy.end());
  if (deviceDamping) {
    s.hasDeviceDamping = true;
    s.deviceDamping = *deviceDamping;
    s.energyInWithDevice_mJ = withDevice;
  }
  // The largest fall of E within the window: for each frame, the highest E of
  // the frames at most 100 ms before it (a deque of indices of falling E).
  std::deque<size_t> highest;
  for (size_t j = 0; j < n; ++j) {
    while (!highest.empty() && frames[j].t - frames[highest.front()].t > kGenerationWindow + 1e-9) highest.pop_front();
    while (!highest.empty() && energy[highest.back()] <= energy[j]) highest.pop_back();
    highest.push_back(j);
    s.maxGeneratedPer100ms_mJ = std::max(s.maxGeneratedPer100ms_mJ, energy[highest.front()] - energy[j]);
  }
}

// The spring energy its anchor's moves added beyond the device's own motion:
// the spring of frame k, s_k, held while the device moved dx would be s_k - dx.
void proxyGenerated(const HapticFrame* frames, size_t n, const RenderingGains& gains, HapticStats& s) {
  for (size_t k = 1; k < n; ++k) {
    const HapticFrame& a = frames[k - 1];
    const HapticFrame& b = frames[k];
    if (frameHasNaN(a) || frameHasNaN(b)) continue;
    const Vec3 held = a.penetration * a.normal - (b.device - a.device);  // mm
    const Vec3 spring = b.penetration * b.normal;                        // mm
    s.proxyGenerated_mJ += std::max(0.0, 0.5 * gains.stiffness * (spring.squaredNorm() - held.squaredNorm()));
  }
}

// |dF| - k |dx| - b |dv| per frame, with the device velocity by backward
// differences as the device computes it (zero at the first frame).
void unexplainedSteps(const HapticFrame* frames, size_t n, const RenderingGains& gains, HapticStats& s) {
  std::vector<double> unexplained;
  unexplained.reserve(n);
  Vec3 velocity = Vec3::Zero();  // mm/s, of the previous frame
  for (size_t k = 1; k < n; ++k) {
    const HapticFrame& a = frames[k - 1];
    const HapticFrame& b = frames[k];
    if (frameHasNaN(a) || frameHasNaN(b)) {
      velocity = Vec3::Zero();
      continue;
    }
    const Vec3 dx = b.device - a.device;
    const double dt = b.t - a.t;
    const Vec3 v = dt > 0 ? Vec3(dx / dt) : Vec3::Zero();
    const double explained = gains.stiffness * dx.norm() + gains.damping * (v - velocity).norm();
    unexplained.push_back(std::max(0.0, (b.force - a.force).norm() - explained));
    velocity = v;
  }
  s.hasUnexplainedSteps = true;
  if (unexplained.empty()) return;
  s.unexplainedStepMax = *std::max_element(unexplained.begin(), unexplained.end());
  s.unexplainedStepP99 = percentile(unexplained, 0.99);
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
      const Vec3& previous = m_frames[i - 1].force;
      steps.push_back((f.force - previous).norm());
      if (force > kReversalForce && previous.norm() > kReversalForce && f.force.dot(previous) < 0) ++s.forceReversals;
    }
  }
  const size_t finite = m_size - s.nanFrames;
  if (finite > 0) s.forceMean = forceSum / static_cast<double>(finite);
  if (s.contactFrames > 0) s.penetrationMean = penetrationSum / static_cast<double>(s.contactFrames);
  if (!steps.empty()) {
    s.forceStepP99 = percentile(steps, 0.99);
    s.forceStepMax = steps.back();
  }
  observePassivity(m_frames.data(), m_size, m_deviceDamping, s);
  if (m_gains) {
    unexplainedSteps(m_frames.data(), m_size, *m_gains, s);
    proxyGenerated(m_frames.data(), m_size, *m_gains, s);
  }
  return s;
}

}  // namespace trephine
