#include "plugins/fem/TLEDState.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace trephine::fem {

TLEDState::TLEDState(const TLEDModel& model) : m_model(&model) {
  const size_t n = model.nodeCount();
  m_u.assign(kNodeStride * n, 0.0);
  m_uPrev.assign(kNodeStride * n, 0.0);
  m_f.assign(kNodeStride * n, 0.0);
  m_externalForces.reserve(n);
  m_externalSlot.assign(n, -1);
  m_nodeDamping.reserve(n);
  m_dampingSlot.assign(n, -1);
  for (const TLEDModel::HeldAxis& h : model.m_held) m_u[h.index] = m_uPrev[h.index] = h.value;
}

TLEDState::TLEDState(const TLEDState& other) { *this = other; }

TLEDState& TLEDState::operator=(const TLEDState& other) {
  if (this == &other) return *this;
  m_model = other.m_model;
  m_u = other.m_u;
  m_uPrev = other.m_uPrev;
  m_f = other.m_f;
  // A copy of a vector has only the capacity its elements need: the loads
  // keep room for every node, so that setting one never allocates.
  m_externalForces.reserve(m_u.size() / kNodeStride);
  m_externalForces = other.m_externalForces;
  m_externalSlot = other.m_externalSlot;
  m_nodeDamping.reserve(m_u.size() / kNodeStride);
  m_nodeDamping = other.m_nodeDamping;
  m_dampingSlot = other.m_dampingSlot;
  m_steps = other.m_steps;
  m_invertedNow = other.m_invertedNow;
  m_restingSteps = other.m_restingSteps;
  m_resting = other.m_resting;
  m_counts = other.m_counts;
  return *this;
}

void TLEDState::setExternalForce(int32_t node, const Vec3& force_mN) {
  const int32_t k = m_model->m_internal[node];
  int32_t& slot = m_externalSlot[k];
  if (slot < 0) {
    slot = int32_t(m_externalForces.size());
    m_externalForces.push_back({k, Vec3::Zero()});  // within the capacity reserved for every node
  }
  m_externalForces[slot].force = force_mN;
}

void TLEDState::setNodeDamping(int32_t node, double damping) {
  const int32_t k = m_model->m_internal[node];
  int32_t& slot = m_dampingSlot[k];
  if (damping > 0) {
    if (slot < 0) {
      slot = int32_t(m_nodeDamping.size());
      m_nodeDamping.push_back({k, 0.0, {}});  // within the capacity reserved for every node
    }
    m_nodeDamping[slot].damping = damping;
  } else if (slot >= 0) {
    // The last entry takes the removed one's place.
    m_nodeDamping[slot] = m_nodeDamping.back();
    m_dampingSlot[m_nodeDamping[slot].node] = slot;
    m_nodeDamping.pop_back();
    slot = -1;
  }
}

void TLEDState::clearExternalForces() {
  for (const ExternalForce& f : m_externalForces) m_externalSlot[f.node] = -1;
  m_externalForces.clear();
}

bool TLEDState::loaded() const {
  if (!m_model->m_bodyAcceleration.isZero(0.0)) return true;
  for (const ExternalForce& e : m_externalForces)
    if (!e.force.isZero(0.0)) return true;
  for (const TLEDModel::HeldAxis& h : m_model->m_held)
    if (h.value != 0) return true;
  return false;
}

void TLEDState::step() {
  const TLEDModel& model = *m_model;
  // At rest with nothing to move it, the step's answer is rest: it is not
  // computed (the element loop would return forces of rounding size, 1e-16
  // of the moduli). A brain nobody touches costs nothing.
  if (m_resting) {
    if (!loaded()) {
      ++m_steps;
      ++m_restingSteps;
      m_invertedNow = 0;
      return;
    }
    m_resting = false;
  }
  // The held axes at their values now and one step ago (a value the model
  // changed since the last step is a prescribed displacement).
  for (const TLEDModel::HeldAxis& h : model.m_held) m_u[h.index] = m_uPrev[h.index] = h.value;
  const ElementStepCounts counts = model.forcesInto(m_u.data(), m_f.data());
  m_invertedNow = counts.inverted;
  m_counts.inverted += counts.inverted;
  m_counts.farFromRest += counts.farFromRest;
  for (const ExternalForce& e : m_externalForces)
    for (size_t axis = 0; axis < 3; ++axis) m_f[kNodeStride * e.node + axis] -= e.force[axis];
  const double dt = model.m_dt, damping = model.m_damping;
  const Vec3& acceleration = model.m_bodyAcceleration;
  const double denominator = 1 + damping * dt / 2;
  const double now = 2 / denominator, before = (1 - damping * dt / 2) / denominator;
  // A node's (x, y, z, 0) as one vector: the update is the same four
  // operations on each, node after node.
  using NodeVector = double __attribute__((vector_size(kNodeStride * sizeof(double))));
  const NodeVector gravity = {dt * dt * acceleration.x() / denominator, dt * dt * acceleration.y() / denominator,
                              dt * dt * acceleration.z() / denominator, 0.0};  // mm per step
  const size_t n = model.m_mass.size();
  const double* u = m_u.data();
  const double* f = m_f.data();
  const double* scale = model.m_stepScale.data();
  double* next = m_uPrev.data();  // u- is read and overwritten by u+ at the same index
  for (NodeDamping& d : m_nodeDamping) std::copy_n(next + kNodeStride * size_t(d.node), kNodeStride, d.before);
  for (size_t k = 0; k < n; ++k) {
    const size_t i = kNodeStride * k;
    NodeVector current, previous, force;
    std::memcpy(&current, u + i, sizeof current);
    std::memcpy(&previous, next + i, sizeof previous);
    std::memcpy(&force, f + i, sizeof force);
    const NodeVector value = now * current - before * previous - scale[k] * force + gravity;
    std::memcpy(next + i, &value, sizeof value);
  }
  // The damped nodes again, with their own damping added to the mass-proportional one.
  for (const NodeDamping& d : m_nodeDamping) {
    const double mass = model.m_mass[d.node];
    if (!(mass > 0)) continue;
    const double half = (damping + d.damping / mass) * dt / 2;
    for (size_t axis = 0; axis < 3; ++axis) {
      const size_t i = kNodeStride * size_t(d.node) + axis;
      next[i] =
          (2 * u[i] - (1 - half) * d.before[axis] - dt * dt / mass * f[i] + dt * dt * acceleration[axis]) / (1 + half);
    }
  }
  for (const TLEDModel::HeldAxis& h : model.m_held) next[h.index] = h.value;
  std::swap(m_u, m_uPrev);
  ++m_steps;
}

void TLEDState::setDisplacements(std::span<const Vec3> u, std::span<const Vec3> uPrevious) {
  if (u.size() != m_model->nodeCount() || uPrevious.size() != m_model->nodeCount())
    throw std::invalid_argument("one displacement per node");
  for (size_t i = 0; i < m_model->nodeCount(); ++i)
    for (size_t axis = 0; axis < 3; ++axis) {
      const size_t index = m_model->index(int32_t(i), axis);
      m_u[index] = u[i][axis];
      m_uPrev[index] = uPrevious[i][axis];
    }
  for (const TLEDModel::HeldAxis& h : m_model->m_held) m_u[h.index] = m_uPrev[h.index] = h.value;
  m_resting = false;
}

void TLEDState::resetToRest() {
  std::fill(m_u.begin(), m_u.end(), 0.0);
  std::fill(m_uPrev.begin(), m_uPrev.end(), 0.0);
  for (const TLEDModel::HeldAxis& h : m_model->m_held) m_u[h.index] = m_uPrev[h.index] = h.value;
  m_resting = true;
}

TLEDState::WrittenShape TLEDState::writePositions(std::span<Vec3> positions) const {
  double largestSquared = 0, largestMoveSquared = 0;
  bool finite = true;
  for (size_t i = 0; i < m_model->m_rest.size(); ++i) {
    const double* d = &m_u[m_model->index(int32_t(i), 0)];
    const Vec3 u(d[0], d[1], d[2]);
    const Vec3 p = m_model->m_rest[i] + u;
    const double squared = u.squaredNorm(), moveSquared = (p - positions[i]).squaredNorm();
    positions[i] = p;
    // std::max would drop a NaN. The shape before may be a diverged one: then the move is unknown.
    finite = finite && std::isfinite(squared) && p.allFinite();
    largestSquared = std::max(largestSquared, squared);
    largestMoveSquared = std::isfinite(moveSquared) ? std::max(largestMoveSquared, moveSquared) : INFINITY;
  }
  if (!finite) return {INFINITY, INFINITY};
  return {std::sqrt(largestSquared), std::sqrt(largestMoveSquared)};
}

void TLEDState::internalForces(std::span<Vec3> forces) const {
  m_model->forcesInto(m_u.data(), m_f.data());
  for (size_t i = 0; i < m_model->nodeCount(); ++i) {
    const double* f = &m_f[m_model->index(int32_t(i), 0)];
    forces[i] = Vec3(f[0], f[1], f[2]);
  }
}

double TLEDState::kineticEnergy() const {
  if (m_model->m_dt <= 0) return 0;
  double twice = 0;  // kg mm^2 / s^2
  for (size_t k = 0; k < m_model->m_mass.size(); ++k) {
    double v2 = 0;
    for (size_t axis = 0; axis < 3; ++axis) {
      const double v = m_u[kNodeStride * k + axis] - m_uPrev[kNodeStride * k + axis];
      v2 += v * v;
    }
    twice += m_model->m_mass[k] * v2;
  }
  return 0.5 * twice / (m_model->m_dt * m_model->m_dt);
}

Mat3 TLEDState::deformationGradient(size_t k) const {
  const TLEDElements& el = m_model->m_elements;
  Mat3 F = Mat3::Identity();
  const double* u0 = &m_u[size_t(el.nodeOffset[0][k])];
  for (int a = 1; a < 4; ++a) {
    const double* ua = &m_u[size_t(el.nodeOffset[a][k])];
    const Vec3 d(ua[0] - u0[0], ua[1] - u0[1], ua[2] - u0[2]);
    const Eigen::RowVector3d g(el.grad[3 * (a - 1)][k], el.grad[3 * (a - 1) + 1][k], el.grad[3 * (a - 1) + 2][k]);
    F += d * g;
  }
  return F;
}

double TLEDState::strainEnergy() const {
  const TLEDElements& el = m_model->m_elements;
  double energy = 0;
  for (size_t k = 0; k < el.count; ++k)
    energy += neoHookeanEnergy(deformationGradient(k), {el.muVolume[k], el.kappaVolume[k]});  // the volume is in the moduli
  return energy;
}

void TLEDState::vonMisesStress(std::span<float> out, size_t first, size_t count) const {
  const TLEDElements& el = m_model->m_elements;
  // In the model's order (neighbours share nodes in cache), out in the mesh's.
  const size_t end = std::min(el.count, first + std::min(count, el.count));
  for (size_t k = first; k < end; ++k) {
    const size_t e = size_t(m_model->m_elementExternal[k]);
    if (e >= out.size()) continue;
    const double volume = m_model->m_volume[k];
    const ElasticModuli moduli{el.muVolume[k] / volume, el.kappaVolume[k] / volume};
    out[e] = float(neoHookeanVonMises(deformationGradient(k), moduli, kMinIsochoricJ));
  }
}

}  // namespace trephine::fem
