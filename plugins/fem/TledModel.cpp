#include "plugins/fem/TledModel.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace trephine::fem {

namespace {

void checkMaterial(const ElementMaterial& m, size_t index) {
  const auto where = [&] { return " (material " + std::to_string(index) + ")"; };
  if (!(m.density > 0) || !std::isfinite(m.density)) throw std::invalid_argument("density must be > 0" + where());
  if (!(m.youngModulus > 0) || !std::isfinite(m.youngModulus))
    throw std::invalid_argument("Young's modulus must be > 0" + where());
  if (!(m.poissonRatio > -1 && m.poissonRatio < 0.5))
    throw std::invalid_argument("Poisson's ratio must be in (-1, 0.5)" + where());
}

}  // namespace

TledModel::TledModel(std::span<const Vec3> restNodes, std::span<const tetra::TetIndices> tets,
                     std::span<const ElementMaterial> materials)
    : m_rest(restNodes.begin(), restNodes.end()) {
  if (materials.size() != 1 && materials.size() != tets.size())
    throw std::invalid_argument("one material for all elements or one per element (" +
                                std::to_string(materials.size()) + " for " + std::to_string(tets.size()) + ")");
  for (size_t i = 0; i < materials.size(); ++i) checkMaterial(materials[i], i);
  const size_t n = m_rest.size();
  TledElements& el = m_elements;
  el.count = tets.size();
  el.padded = (el.count + TledElements::kLanes - 1) / TledElements::kLanes * TledElements::kLanes;
  for (auto& v : el.node) v.assign(el.padded, 0);
  for (auto& v : el.grad) v.assign(el.padded, 0.0);
  el.volume.assign(el.padded, 0.0);
  el.mu.assign(el.padded, 0.0);
  el.kappa.assign(el.padded, 0.0);
  m_mass.assign(n, 0.0);
  m_length.reserve(el.count);
  m_density.reserve(el.count);
  for (size_t e = 0; e < el.count; ++e) {
    const tetra::TetIndices& t = tets[e];
    for (int a = 0; a < 4; ++a) {
      if (t[a] < 0 || size_t(t[a]) >= n)
        throw std::invalid_argument("element " + std::to_string(e) + " names node " + std::to_string(t[a]) +
                                    " of " + std::to_string(n));
      el.node[a][e] = t[a];
    }
    const Vec3 &X0 = m_rest[t[0]], &X1 = m_rest[t[1]], &X2 = m_rest[t[2]], &X3 = m_rest[t[3]];
    Mat3 D;
    D.col(0) = X1 - X0;
    D.col(1) = X2 - X0;
    D.col(2) = X3 - X0;
    const double volume = D.determinant() / 6.0;
    if (!(volume > 0))
      throw std::invalid_argument("element " + std::to_string(e) + " has rest volume " + std::to_string(volume) +
                                  " mm^3 (inverted or degenerate)");
    // Barycentric coordinates of nodes 1..3 are D^-1 (X - X0): their gradients are the rows of D^-1.
    const Mat3 Dinv = D.inverse();
    for (int a = 0; a < 3; ++a)
      for (int j = 0; j < 3; ++j) el.grad[3 * a + j][e] = Dinv(a, j);
    const ElementMaterial& material = materials.size() == 1 ? materials[0] : materials[e];
    const ElasticModuli moduli = ElasticModuli::fromYoung(material.youngModulus, material.poissonRatio);
    el.volume[e] = volume;
    el.mu[e] = moduli.mu;
    el.kappa[e] = moduli.kappa;
    for (int a = 0; a < 4; ++a) m_mass[t[a]] += 0.25 * material.density * volume;
    // Characteristic length 1 / |grad N|, |grad N|^2 the sum over the four
    // nodes of |grad N_a|^2 = 1 / h_a^2 (h_a the height over node a): the
    // element's stiffest mode is at most (lambda + 2 mu) V |grad N|^2, so with
    // a quarter of its mass at each node its highest frequency is at most
    // 2 c |grad N|, and central differences are stable below 1 / (c |grad N|).
    // (Checked against the 12 x 12 eigenvalues of random elements: the bound is
    // reached.) The mesh's highest frequency is at most its elements' highest.
    double gradientSquared = 0;
    for (int a = 0; a < 3; ++a) gradientSquared += Dinv.row(a).squaredNorm();
    gradientSquared += (Dinv.row(0) + Dinv.row(1) + Dinv.row(2)).squaredNorm();
    m_length.push_back(1 / std::sqrt(gradientSquared));
    m_density.push_back(material.density);
  }
  findCriticalStep();
  for (int axis = 0; axis < 3; ++axis) {
    m_u[axis].assign(n, 0.0);
    m_uPrev[axis].assign(n, 0.0);
    m_f[axis].assign(n, 0.0);
    m_external[axis].assign(n, 0.0);
    m_held[axis].assign(n, 0.0);
    m_free[axis].assign(n, 1.0);
    // A node no element holds has no mass: it stays where it is.
    for (size_t i = 0; i < n; ++i)
      if (m_mass[i] == 0) m_free[axis][i] = 0.0;
  }
  m_stepScale.assign(n, 0.0);
}

void TledModel::findCriticalStep() {
  m_criticalStep = INFINITY;
  const TledElements& el = m_elements;
  for (size_t e = 0; e < el.count; ++e) {
    const double step = m_length[e] / ElasticModuli{el.mu[e], el.kappa[e]}.dilatationalWaveSpeed(m_density[e]);
    if (step < m_criticalStep) {
      m_criticalStep = step;
      m_criticalElement = e;
    }
  }
}

void TledModel::assignMaterial(std::span<const int32_t> elements, const ElementMaterial& material) {
  checkMaterial(material, 0);
  const ElasticModuli moduli = ElasticModuli::fromYoung(material.youngModulus, material.poissonRatio);
  TledElements& el = m_elements;
  for (int32_t e : elements) {
    const double change = 0.25 * (material.density - m_density[e]) * el.volume[e];
    for (int a = 0; a < 4; ++a) m_mass[el.node[a][e]] += change;
    m_density[e] = material.density;
    el.mu[e] = moduli.mu;
    el.kappa[e] = moduli.kappa;
  }
  findCriticalStep();
  if (m_dt > 0) setTimeStep(m_dt, m_damping);
}

double TledModel::criticalTimeStep(double damping) const {
  const double xi = damping * m_criticalStep / 4;  // damping ratio of the highest mode, 2 / dt_cr rad/s
  return m_criticalStep * (std::sqrt(1 + xi * xi) - xi);
}

void TledModel::setTimeStep(double dt, double damping) {
  if (!(dt > 0) || !std::isfinite(dt)) throw std::invalid_argument("time step must be > 0 s");
  if (!(damping >= 0) || !std::isfinite(damping)) throw std::invalid_argument("damping must be >= 0 1/s");
  m_dt = dt;
  m_damping = damping;
  const double denominator = 1 + damping * dt / 2;
  for (size_t i = 0; i < m_mass.size(); ++i)
    m_stepScale[i] = m_mass[i] > 0 ? dt * dt / (m_mass[i] * denominator) : 0.0;
}

void TledModel::fixNode(int32_t node, const Vec3& displacement, unsigned axes) {
  for (int axis = 0; axis < 3; ++axis) {
    if (!(axes & (1u << axis))) continue;
    m_free[axis][node] = 0.0;
    m_held[axis][node] = displacement[axis];
    m_u[axis][node] = m_uPrev[axis][node] = displacement[axis];
  }
}

void TledModel::setExternalForce(int32_t node, const Vec3& force_mN) {
  for (int axis = 0; axis < 3; ++axis) m_external[axis][node] = force_mN[axis];
}

void TledModel::clearExternalForces() {
  for (auto& f : m_external) std::fill(f.begin(), f.end(), 0.0);
}

void TledModel::step() {
  for (auto& f : m_f) std::fill(f.begin(), f.end(), 0.0);
  const ElementStepCounts counts = accumulateInternalForces(m_elements, m_u[0].data(), m_u[1].data(), m_u[2].data(),
                                                            m_f[0].data(), m_f[1].data(), m_f[2].data());
  m_invertedNow = counts.inverted;
  m_counts.inverted += counts.inverted;
  m_counts.farFromRest += counts.farFromRest;
  const double denominator = 1 + m_damping * m_dt / 2;
  const double now = 2 / denominator, before = (1 - m_damping * m_dt / 2) / denominator;
  const size_t n = m_mass.size();
  for (int axis = 0; axis < 3; ++axis) {
    const double gravity = m_dt * m_dt * m_bodyAcceleration[axis] / denominator;  // mm per step
    const double* u = m_u[axis].data();
    const double* f = m_f[axis].data();
    const double* external = m_external[axis].data();
    const double* free = m_free[axis].data();
    const double* held = m_held[axis].data();
    const double* scale = m_stepScale.data();
    double* next = m_uPrev[axis].data();  // u- is read and overwritten by u+ at the same index
    for (size_t i = 0; i < n; ++i) {
      const double moved = now * u[i] - before * next[i] + scale[i] * (external[i] - f[i]) + gravity;
      next[i] = free[i] * moved + (1 - free[i]) * held[i];
    }
    std::swap(m_u[axis], m_uPrev[axis]);
  }
  ++m_steps;
}

void TledModel::setDisplacements(std::span<const Vec3> u, std::span<const Vec3> uPrevious) {
  if (u.size() != nodeCount() || uPrevious.size() != nodeCount())
    throw std::invalid_argument("one displacement per node");
  for (size_t i = 0; i < nodeCount(); ++i)
    for (int axis = 0; axis < 3; ++axis) {
      m_u[axis][i] = m_free[axis][i] != 0 ? u[i][axis] : m_held[axis][i];
      m_uPrev[axis][i] = m_free[axis][i] != 0 ? uPrevious[i][axis] : m_held[axis][i];
    }
}

double TledModel::writePositions(std::span<Vec3> positions) const {
  double largestSquared = 0;
  for (size_t i = 0; i < m_rest.size(); ++i) {
    const Vec3 u(m_u[0][i], m_u[1][i], m_u[2][i]);
    positions[i] = m_rest[i] + u;
    largestSquared = std::max(largestSquared, u.squaredNorm());
  }
  return std::sqrt(largestSquared);
}

double TledModel::totalMass() const {
  double total = 0;
  for (double m : m_mass) total += m;
  return total;
}

void TledModel::internalForces(std::span<Vec3> forces) const {
  std::vector<double> f[3];
  for (auto& v : f) v.assign(nodeCount(), 0.0);
  accumulateInternalForces(m_elements, m_u[0].data(), m_u[1].data(), m_u[2].data(), f[0].data(), f[1].data(),
                           f[2].data());
  for (size_t i = 0; i < nodeCount(); ++i) forces[i] = Vec3(f[0][i], f[1][i], f[2][i]);
}

double TledModel::kineticEnergy() const {
  if (m_dt <= 0) return 0;
  double twice = 0;  // kg mm^2 / s^2
  for (size_t i = 0; i < m_mass.size(); ++i) {
    const Vec3 v(m_u[0][i] - m_uPrev[0][i], m_u[1][i] - m_uPrev[1][i], m_u[2][i] - m_uPrev[2][i]);
    twice += m_mass[i] * v.squaredNorm();
  }
  return 0.5 * twice / (m_dt * m_dt);
}

double TledModel::strainEnergy() const {
  const TledElements& el = m_elements;
  double energy = 0;
  for (size_t e = 0; e < el.count; ++e) {
    Mat3 F = Mat3::Identity();
    const int32_t n0 = el.node[0][e];
    for (int a = 1; a < 4; ++a) {
      const int32_t na = el.node[a][e];
      const Vec3 d = displacement(na) - displacement(n0);
      const Eigen::RowVector3d g(el.grad[3 * (a - 1)][e], el.grad[3 * (a - 1) + 1][e], el.grad[3 * (a - 1) + 2][e]);
      F += d * g;
    }
    energy += el.volume[e] * neoHookeanEnergy(F, {el.mu[e], el.kappa[e]});
  }
  return energy;
}

}  // namespace trephine::fem
