#include "plugins/haptics/HandModel.h"

namespace trephine::haptics {

namespace {
// N / kg is m/s^2, which is 1000 mm/s^2.
constexpr double kMmPerM = 1000.0;
}  // namespace

bool HandParameters::integratesStably(double rateHz, int substeps) const {
  if (!(mass() > 0) || !(rateHz > 0) || substeps < 1) return false;
  const double h = 1.0 / (rateHz * substeps);                         // s
  const double w2 = kMmPerM * gripStiffness / mass();                 // 1/s^2
  const double c = kMmPerM * (gripDamping + deviceDamping) / mass();  // 1/s
  return h * h * w2 + 2.0 * h * c <= 1.0;
}

void HandModel::reset(const Vec3& position) {
  m_position = position;
  m_velocity = Vec3::Zero();
}

void HandModel::advance(const HandParameters& p, const ScriptedPath& intent, double t, double dt, int substeps,
                        const Vec3& force_N) {
  const double h = dt / substeps;             // s
  const double perMass = kMmPerM / p.mass();  // (mm/s^2) per N
  Vec3 intentHere = intent.at(t);
  for (int i = 0; i < substeps; ++i) {
    // The intended velocity over this substep, from the intent's positions at its ends.
    const Vec3 intentNext = intent.at(t + (i + 1) * h);
    const Vec3 intentVelocity = (intentNext - intentHere) / h;  // mm/s
    const Vec3 pull = p.gripStiffness * (intentHere - m_position) + p.gripDamping * (intentVelocity - m_velocity) -
                      p.deviceDamping * m_velocity;  // N
    // Semi-implicit Euler: the new velocity moves the position.
    m_velocity += h * perMass * (force_N + pull);
    m_position += h * m_velocity;
    intentHere = intentNext;
  }
}

}  // namespace trephine::haptics
