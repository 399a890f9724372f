#include "plugins/haptics/ScriptedPath.h"

#include <algorithm>

namespace trephine::haptics {

double minimumJerk(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
}

double easedTime(double s, double total, double ramp) {
  // Integral of the minimum-jerk rate, F(u) = 2.5u^4 - 3u^5 + u^6, F(1) = 1/2.
  const auto rampIntegral = [](double u) { return u * u * u * u * (2.5 + u * (-3.0 + u)); };
  s = std::clamp(s, 0.0, total);
  if (ramp <= 0) return s;
  if (s < ramp) return ramp * rampIntegral(s / ramp);
  if (s > total - ramp) return (total - ramp) - ramp * rampIntegral((total - s) / ramp);
  return s - 0.5 * ramp;
}

void ScriptedPath::moveTo(const Vec3& to, double duration) {
  const Vec3 from = m_current;
  if (duration <= 0) {
    m_current = to;
    return;
  }
  follow(duration, [from, to, duration](double s) { return Vec3(from + (to - from) * minimumJerk(s / duration)); });
  m_current = to;
}

void ScriptedPath::hold(double duration) {
  const Vec3 at = m_current;
  follow(duration, [at](double) { return at; });
}

void ScriptedPath::follow(double duration, std::function<Vec3(double)> position) {
  if (duration <= 0) return;
  m_current = position(duration);
  m_segments.push_back({m_duration, duration, std::move(position)});
  m_duration += duration;
}

Vec3 ScriptedPath::at(double t) const {
  if (m_segments.empty()) return m_current;
  // Segments are few (tens); a binary search keeps long random walks cheap too.
  const auto it = std::upper_bound(m_segments.begin(), m_segments.end(), t,
                                   [](double time, const Segment& s) { return time < s.t0; });
  const Segment& segment = it == m_segments.begin() ? m_segments.front() : *(it - 1);
  return segment.position(std::clamp(t - segment.t0, 0.0, segment.duration));
}

SeededRandom::SeededRandom(uint64_t seed) : m_state(seed ^ 0x9E3779B97F4A7C15ull) {}

double SeededRandom::uniform() {
  // splitmix64: small, fast and fully specified.
  uint64_t z = (m_state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

}  // namespace trephine::haptics
