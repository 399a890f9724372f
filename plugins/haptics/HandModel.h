#pragma once
// A hand holding a device handle, each coordinate on its own: handle and hand
// move as one mass under the rendered force F, the grip (a spring and a damper
// pulling toward where the hand means to be) and the device's own friction:
//
//   (m_device + m_hand) x'' = F + k_grip (x_intent - x) + b_grip (v_intent - v) - b_device v
//
// F is held over the whole frame (zero-order hold: a device's amplifier keeps
// the last command until the next), and the motion is integrated in substeps
// with semi-implicit Euler, so the closed loop sees the 1 kHz sampling as a
// real hand does. Allocation-free: it runs in the haptic loop.
#include "framework/math/Math.h"
#include "plugins/haptics/ScriptedPath.h"

namespace trephine::haptics {

struct HandParameters {
  double deviceMass = 0;     // kg, apparent mass of the handle
  double deviceDamping = 0;  // N*s/mm, the mechanism's viscous friction
  double handMass = 0;       // kg
  double gripStiffness = 0;  // N/mm, pull toward the intended position
  double gripDamping = 0;    // N*s/mm, pull toward the intended velocity

  double mass() const { return deviceMass + handMass; }  // kg
  // Whether `substeps` steps per frame at `rateHz` integrate this hand well:
  // semi-implicit Euler on a spring-damper is stable for h^2 w^2 + 2 h c < 4
  // (step h, s; w^2 = k/m, 1/s^2; c = b/m, 1/s); a quarter of that keeps the
  // integration error small. The rendered force does not enter: it is held.
  bool integratesStably(double rateHz, int substeps) const;
};

class HandModel {
 public:
  // At rest at `position` (mm).
  void reset(const Vec3& position);
  // Moves on from t to t + dt (s) in `substeps` equal steps under `force_N`,
  // held constant, toward `intent` (positions in mm).
  void advance(const HandParameters& p, const ScriptedPath& intent, double t, double dt, int substeps,
               const Vec3& force_N);

  const Vec3& position() const { return m_position; }  // mm
  const Vec3& velocity() const { return m_velocity; }  // mm/s

 private:
  Vec3 m_position = Vec3::Zero();
  Vec3 m_velocity = Vec3::Zero();
};

}  // namespace trephine::haptics
