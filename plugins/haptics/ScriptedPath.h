#pragma once
// Tool motions as functions of time, built once before the run and evaluated
// without allocation in the haptic loop. Moves between points use a
// minimum-jerk (quintic) profile so the velocity is continuous at every corner.
#include <cstdint>
#include <functional>
#include <vector>

#include "framework/math/Math.h"

namespace trephine::haptics {

class ScriptedPath {
 public:
  // Straight move to `to` taking `duration` s (quintic time profile).
  void moveTo(const Vec3& to, double duration);
  // Stay at the current point for `duration` s.
  void hold(double duration);
  // A custom stretch: `position(s)` for s in [0, duration] s; must start where the path is.
  void follow(double duration, std::function<Vec3(double)> position);
  void start(const Vec3& at) { m_current = at; }

  const Vec3& end() const { return m_current; }
  double duration() const { return m_duration; }
  // Position (mm) at t (s); holds the last point after the end.
  Vec3 at(double t) const;

 private:
  struct Segment {
    double t0 = 0, duration = 0;
    std::function<Vec3(double)> position;
  };
  std::vector<Segment> m_segments;
  Vec3 m_current = Vec3::Zero();
  double m_duration = 0;
};

// Quintic minimum-jerk blend: 0 at u=0, 1 at u=1, zero velocity and acceleration at both ends.
double minimumJerk(double u);

// A time warp that starts a steady motion from rest and brings it back to
// rest: its rate rises from 0 to 1 over the first `ramp` s with the
// minimum-jerk profile, stays 1, and falls back over the last `ramp` s. Maps
// [0, total] onto [0, total - ramp]; needs total >= 2 ramp.
double easedTime(double s, double total, double ramp);

// Uniform numbers from a seed, identical on every platform (the standard
// distributions are not specified bit for bit, the engine is).
class SeededRandom {
 public:
  explicit SeededRandom(uint64_t seed);
  double uniform();  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

 private:
  uint64_t m_state;
};

}  // namespace trephine::haptics
