#pragma once
// Preallocated per-frame record of the haptic loop. The loop writes one frame
// per tick without allocating; the run writes the log to trace.csv and derives
// the summary's `haptics` figures from it after the run (or after an interrupt).
#include <cstddef>
#include <optional>
#include <vector>

#include "framework/logs/HapticFrame.h"

namespace trephine {

struct HapticStats {
  size_t frames = 0;
  size_t contactFrames = 0;
  double forceMax = 0, forceMean = 0;              // N, |F|
  double forceStepMax = 0, forceStepP99 = 0;       // N, |F_k - F_{k-1}|
  double penetrationMax = 0, penetrationMean = 0;  // mm, over contact frames
  size_t nanFrames = 0;
  size_t proxyInsideFrames = 0;
  size_t droppedFrames = 0;  // frames beyond the preallocated capacity

  // Hannaford and Ryu (2002) passivity observer with the force held over each
  // frame: the energy the hand has put into the simulated environment by frame
  // n, E(n) = -sum_{k<n} F_k . (x_{k+1} - x_k) (N on the hand, device mm: mJ).
  // E rises while the environment stores or dissipates energy and falls while
  // it gives energy back; an environment passive as sampled never goes below 0.
  double energyIn_mJ = 0;              // final E
  double minEnergyIn_mJ = 0;           // most negative E: energy the rendering generated
  double maxGeneratedPer100ms_mJ = 0;  // largest fall of E within 100 ms (a limit cycle, even when cutting dissipates)
  // The same with the device's own damping b counted (only when the writer
  // handed it, from a device with dynamics): E_b(n) = E(n) + sum_{k<n} b
  // |x_{k+1} - x_k|^2 / T_k, the energy the hand has put into the device and
  // the environment together. b |dx|^2 / T is the least a damper b dissipates
  // while the device moves dx in T (Cauchy-Schwarz; equal at constant speed),
  // and the hold of a spring k gives back at most k |dx|^2 / 2 more than the
  // spring held: the sampled-data check b > k T / 2 is what keeps E_b at or
  // above what the spring holds, so E_b is the figure that check speaks of. A
  // virtual environment alone (E) is never passive with b = 0 in the renderer.
  bool hasDeviceDamping = false;
  double deviceDamping = 0;             // N*s/mm, b
  double energyInWithDevice_mJ = 0;     // final E_b
  double minEnergyInWithDevice_mJ = 0;  // most negative E_b
  // Energy the spring gained from its anchor moving away from where the
  // device is (the proxy re-projected outward or sideways), beyond the
  // device's own motion: sum of max(0, k/2 (|s_{k+1}|^2 - |s_k - dx_k|^2)),
  // s = penetration x normal the rendered spring (mm), k the renderer's
  // stiffness (below its force clamp; an upper bound at the clamp). Nothing
  // pays for it, whatever the device's damping. Only when the renderer handed its gains.
  double proxyGenerated_mJ = 0;
  // Per frame |dF| - k |dx| - b |dv| (>= 0) with dv the change of the device's
  // backward-difference velocity: the part of a force step the device's own
  // motion does not explain (N). Only when the renderer handed its gains.
  bool hasUnexplainedSteps = false;
  double unexplainedStepMax = 0, unexplainedStepP99 = 0;
  size_t forceReversals = 0;  // frames where F turns back (F_k . F_{k-1} < 0, both above 0.5 N)
};

// Stiffness k (N/mm) and damping b (N*s/mm) of the force renderer writing the log.
struct RenderingGains {
  double stiffness = 0;
  double damping = 0;
};

class HapticFrameLog {
 public:
  explicit HapticFrameLog(size_t capacity = 0) { reserve(capacity); }
  void reserve(size_t capacity) { m_frames.resize(capacity); }

  // Hot path: constant time, no allocation. Frames past the capacity are counted, not stored.
  void record(const HapticFrame& frame) {
    if (m_size < m_frames.size()) {
      m_frames[m_size++] = frame;
    } else {
      ++m_dropped;
    }
  }

  size_t size() const { return m_size; }
  size_t dropped() const { return m_dropped; }
  const HapticFrame& operator[](size_t i) const { return m_frames[i]; }

  // Set once during init by the component that writes the log.
  void setRenderingGains(double stiffness, double damping) { m_gains = RenderingGains{stiffness, damping}; }
  // The damping acting on the device the frames record (N*s/mm), when it has dynamics.
  void setDeviceDamping(double damping) { m_deviceDamping = damping; }

  HapticStats stats() const;

 private:
  std::vector<HapticFrame> m_frames;
  size_t m_size = 0;
  size_t m_dropped = 0;
  std::optional<RenderingGains> m_gains;
  std::optional<double> m_deviceDamping;
};

}  // namespace trephine
