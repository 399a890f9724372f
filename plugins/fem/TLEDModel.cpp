#include "plugins/fem/TLEDModel.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>

namespace trephine::fem {

namespace {

void checkMaterial(const ElementMaterial& m) {
  if (!(m.density > 0) || !std::isfinite(m.density)) throw std::invalid_argument("density must be > 0");
  if (!(m.youngModulus > 0) || !std::isfinite(m.youngModulus))
    throw std::invalid_argument("Young's modulus must be > 0");
  if (!(m.poissonRatio > -1 && m.poissonRatio < 0.5))
    throw std::invalid_argument("Poisson's ratio must be in (-1, 0.5)");
}

// Interleaves the low 21 bits of x, y, z: a Morton (Z-order) code.
uint64_t spreadBits(uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

// Ranks of `points` along the Z-order curve over their box (ties by index).
std::vector<int32_t> zOrder(const std::vector<Vec3>& points) {
  Box3 box;
  for (const Vec3& p : points) box.extend(p);
  const Vec3 scale = Vec3::Constant(double((1 << 21) - 1)).cwiseQuotient((box.max() - box.min()).cwiseMax(1e-12));
  std::vector<uint64_t> codes(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const Vec3 q = (points[i] - box.min()).cwiseProduct(scale);
    codes[i] = spreadBits(uint64_t(q.x())) | spreadBits(uint64_t(q.y())) << 1 | spreadBits(uint64_t(q.z())) << 2;
  }
  std::vector<int32_t> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int32_t a, int32_t b) { return codes[a] < codes[b]; });
  return order;  // order[k]: the k-th point along the curve
}

}  // namespace

TLEDModel::TLEDModel(std::span<const Vec3> restNodes, std::span<const TetIndices> tets,
                     std::span<const ElementMaterial> materials)
    : m_rest(restNodes.begin(), restNodes.end()) {
  if (materials.size() != 1 && materials.size() != tets.size())
    throw std::invalid_argument("one material for all elements or one per element (" +
                                std::to_string(materials.size()) + " for " + std::to_string(tets.size()) + ")");
  for (const ElementMaterial& m : materials) checkMaterial(m);
  const size_t n = m_rest.size();
  if (n > size_t(INT32_MAX) / kNodeStride)
    throw std::invalid_argument(std::to_string(n) + " nodes: the element loop's 32-bit offsets reach " +
                                std::to_string(size_t(INT32_MAX) / kNodeStride));
  for (size_t e = 0; e < tets.size(); ++e)
    for (int32_t node : tets[e])
      if (node < 0 || size_t(node) >= n)
        throw std::invalid_argument("element " + std::to_string(e) + " names node " + std::to_string(node) + " of " +
                                    std::to_string(n));
  // Internal orders along a space-filling curve: nodes by position, elements
  // by centroid, so that the element loop meets its nodes in cache.
  m_external = zOrder(m_rest);
  m_internal.assign(n, 0);
  for (size_t k = 0; k < n; ++k) m_internal[m_external[k]] = int32_t(k);
  std::vector<Vec3> centroids(tets.size());
  for (size_t e = 0; e < tets.size(); ++e)
    centroids[e] = 0.25 * (m_rest[tets[e][0]] + m_rest[tets[e][1]] + m_rest[tets[e][2]] + m_rest[tets[e][3]]);
  // Four stretches of the curve interleaved: the four elements the kernel
  // takes together (and the next four) lie far apart and share no nodes, so
  // the additions of their forces into the nodes do not wait for each other.
  const std::vector<int32_t> curve = zOrder(centroids);
  const size_t quarter = (tets.size() + 3) / 4;
  std::vector<int32_t> elementOrder;
  elementOrder.reserve(tets.size());
  for (size_t q = 0; q < quarter; ++q)
    for (size_t lane = 0; lane < 4; ++lane)
      if (lane * quarter + q < tets.size()) elementOrder.push_back(curve[lane * quarter + q]);
  m_elementInternal.assign(tets.size(), 0);
  for (size_t k = 0; k < tets.size(); ++k) m_elementInternal[elementOrder[k]] = int32_t(k);
  m_elementExternal = elementOrder;

  TLEDElements& el = m_elements;
  el.count = tets.size();
  el.padded = (el.count + TLEDElements::kLanes - 1) / TLEDElements::kLanes * TLEDElements::kLanes;
  for (auto& v : el.nodeOffset) v.assign(el.padded, 0);
  for (auto& v : el.grad) v.assign(el.padded, 0.0);
  el.muVolume.assign(el.padded, 0.0);
  el.kappaVolume.assign(el.padded, 0.0);
  m_volume.assign(el.count, 0.0);
  m_density.assign(el.count, 0.0);
  m_materialDensity.assign(el.count, 0.0);
  m_length.assign(el.count, 0.0);
  m_mass.assign(n, 0.0);
  for (size_t k = 0; k < el.count; ++k) {
    const size_t e = size_t(elementOrder[k]);  // the mesh's index
    const TetIndices& t = tets[e];
    for (int a = 0; a < 4; ++a) el.nodeOffset[a][k] = int32_t(kNodeStride) * m_internal[t[a]];
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
      for (int j = 0; j < 3; ++j) el.grad[3 * a + j][k] = Dinv(a, j);
    const ElementMaterial& material = materials.size() == 1 ? materials[0] : materials[e];
    const ElasticModuli moduli = ElasticModuli::fromYoung(material.youngModulus, material.poissonRatio);
    m_volume[k] = volume;
    m_density[k] = m_materialDensity[k] = material.density;
    el.muVolume[k] = moduli.mu * volume;
    el.kappaVolume[k] = moduli.kappa * volume;
    for (int a = 0; a < 4; ++a) m_mass[size_t(el.nodeOffset[a][k]) / kNodeStride] += 0.25 * material.density * volume;
    // Characteristic length 1 / |grad N|, |grad N|^2 the sum over the four
    // nodes of |grad N_a|^2 = 1 / h_a^2 (h_a the height over node a): the
    // element's stiffest mode is at most (lambda + 2 mu) V |grad N|^2, so with
    // a quarter of its mass at each node its highest frequency is at most
    // 2 c |grad N|, and central differences are stable below 1 / (c |grad N|).
    // (Checked against the 12 x 12 eigenvalues of random elements: the bound is
    // reached.) The mesh's highest frequency is at most its elements' highest.
    double gradientSquared = (Dinv.row(0) + Dinv.row(1) + Dinv.row(2)).squaredNorm();
    for (int a = 0; a < 3; ++a) gradientSquared += Dinv.row(a).squaredNorm();
    m_length[k] = 1 / std::sqrt(gradientSquared);
  }
  m_elementRemoved.assign(el.count, 0);
  m_nodeElements.assign(n, 0);
  for (size_t k = 0; k < el.count; ++k)
    for (int a = 0; a < 4; ++a) ++m_nodeElements[size_t(el.nodeOffset[a][k]) / kNodeStride];
  findCriticalStep();
  m_stepScale.assign(n, 0.0);
  // Every axis of every node held at most once: removing elements (which
  // holds the nodes it frees) never allocates.
  m_held.reserve(3 * n);
  // A node no element holds has no mass: it stays where it is.
  for (size_t k = 0; k < n; ++k)
    if (m_mass[k] == 0)
      for (size_t axis = 0; axis < 3; ++axis) m_held.push_back({kNodeStride * k + axis, 0.0});
}

size_t TLEDModel::removeElements(std::span<const int32_t> elements) {
  TLEDElements& el = m_elements;
  const bool single = el.precision == ElementPrecision::kSingle;
  const double denominator = 1 + m_damping * m_dt / 2;
  size_t count = 0;
  for (const int32_t e : elements) {
    if (e < 0 || size_t(e) >= m_elementInternal.size()) continue;
    const size_t k = size_t(m_elementInternal[size_t(e)]);
    if (m_elementRemoved[k]) continue;
    m_elementRemoved[k] = 1;
    ++count;
    el.muVolume[k] = el.kappaVolume[k] = 0;
    if (single) el.single.muVolume[k] = el.single.kappaVolume[k] = 0;
    const double share = 0.25 * m_density[k] * m_volume[k];
    m_density[k] = m_materialDensity[k] = 0;
    for (int a = 0; a < 4; ++a) {
      const size_t node = size_t(el.nodeOffset[a][k]) / kNodeStride;
      if (--m_nodeElements[node] == 0) {
        // Nothing holds it any more: out of the model, at rest.
        m_mass[node] = 0;
        m_stepScale[node] = 0;
        for (size_t axis = 0; axis < 3; ++axis) {
          const size_t index = kNodeStride * node + axis;
          auto held = std::find_if(m_held.begin(), m_held.end(), [&](const HeldAxis& h) { return h.index == index; });
          if (held == m_held.end()) m_held.push_back({index, 0.0});  // within the reserve
        }
        continue;
      }
      m_mass[node] -= share;
      if (m_dt > 0) m_stepScale[node] = m_dt * m_dt / (m_mass[node] * denominator);
    }
  }
  m_removedCount += count;
  return count;
}

void TLEDModel::findCriticalStep() {
  m_criticalStep = INFINITY;
  for (size_t k = 0; k < m_elements.count; ++k) {
    if (m_elementRemoved[k]) continue;
    const ElasticModuli moduli{m_elements.muVolume[k] / m_volume[k], m_elements.kappaVolume[k] / m_volume[k]};
    const double step = m_length[k] / moduli.dilatationalWaveSpeed(m_density[k]);
    if (step < m_criticalStep) {
      m_criticalStep = step;
      m_criticalElement = k;
    }
  }
  // Reported in the mesh's numbering.
  for (size_t e = 0; e < m_elementInternal.size(); ++e)
    if (size_t(m_elementInternal[e]) == m_criticalElement) {
      m_criticalElement = e;
      break;
    }
}

size_t TLEDModel::elementsBelowStep(double dt) const {
  size_t count = 0;
  for (size_t k = 0; k < m_elements.count; ++k) {
    if (m_elementRemoved[k]) continue;
    const ElasticModuli moduli{m_elements.muVolume[k] / m_volume[k], m_elements.kappaVolume[k] / m_volume[k]};
    if (m_length[k] / moduli.dilatationalWaveSpeed(m_density[k]) < dt) ++count;
  }
  return count;
}

void TLEDModel::assignMaterial(std::span<const int32_t> elements, const ElementMaterial& material) {
  checkMaterial(material);
  const ElasticModuli moduli = ElasticModuli::fromYoung(material.youngModulus, material.poissonRatio);
  TLEDElements& el = m_elements;
  for (int32_t e : elements) {
    const size_t k = size_t(m_elementInternal[e]);
    if (m_elementRemoved[k]) continue;  // resected: stays out
    const double change = 0.25 * (material.density - m_density[k]) * m_volume[k];
    for (int a = 0; a < 4; ++a) m_mass[size_t(el.nodeOffset[a][k]) / kNodeStride] += change;
    m_density[k] = m_materialDensity[k] = material.density;
    el.muVolume[k] = moduli.mu * m_volume[k];
    el.kappaVolume[k] = moduli.kappa * m_volume[k];
  }
  copyToSingle();
  findCriticalStep();
  if (m_dt > 0) setTimeStep(m_dt, m_damping);
}

void TLEDModel::setElementPrecision(ElementPrecision precision) {
  m_elements.precision = precision;
  copyToSingle();
}

void TLEDModel::copyToSingle() {
  TLEDElements& el = m_elements;
  auto copy = [&](const std::vector<double>& from, std::vector<float>& to) {
    if (el.precision == ElementPrecision::kSingle) {
      to.assign(from.begin(), from.end());
    } else {
      to.clear();
      to.shrink_to_fit();
    }
  };
  for (int k = 0; k < 9; ++k) copy(el.grad[k], el.single.grad[k]);
  copy(el.muVolume, el.single.muVolume);
  copy(el.kappaVolume, el.single.kappaVolume);
}

size_t TLEDModel::scaleMassForStep(double dt) {
  // An element's step is L / c, c = sqrt(M / rho): its density times
  // (dt / step)^2 brings its step to dt.
  size_t scaled = 0;
  const TLEDElements& el = m_elements;
  for (size_t k = 0; k < el.count; ++k) {
    if (m_elementRemoved[k]) continue;
    const ElasticModuli moduli{el.muVolume[k] / m_volume[k], el.kappaVolume[k] / m_volume[k]};
    const double step = m_length[k] / moduli.dilatationalWaveSpeed(m_materialDensity[k]);
    const double density = step < dt ? m_materialDensity[k] * (dt / step) * (dt / step) : m_materialDensity[k];
    if (step < dt) ++scaled;
    const double change = 0.25 * (density - m_density[k]) * m_volume[k];
    for (int a = 0; a < 4; ++a) m_mass[size_t(el.nodeOffset[a][k]) / kNodeStride] += change;
    m_density[k] = density;
  }
  findCriticalStep();
  if (m_dt > 0) setTimeStep(m_dt, m_damping);
  return scaled;
}

double TLEDModel::unscaledCriticalTimeStep() const {
  double smallest = std::numeric_limits<double>::infinity();
  const TLEDElements& el = m_elements;
  for (size_t k = 0; k < el.count; ++k) {
    if (m_elementRemoved[k]) continue;
    const ElasticModuli moduli{el.muVolume[k] / m_volume[k], el.kappaVolume[k] / m_volume[k]};
    smallest = std::min(smallest, m_length[k] / moduli.dilatationalWaveSpeed(m_materialDensity[k]));
  }
  return smallest;
}

double TLEDModel::addedMass() const {
  double added = 0;
  for (size_t k = 0; k < m_elements.count; ++k) added += (m_density[k] - m_materialDensity[k]) * m_volume[k];
  return added;
}

double TLEDModel::criticalTimeStep(double damping) const {
  const double xi = damping * m_criticalStep / 4;  // damping ratio of the highest mode, 2 / dt_cr rad/s
  return m_criticalStep * (std::sqrt(1 + xi * xi) - xi);
}

void TLEDModel::setTimeStep(double dt, double damping) {
  if (!(dt > 0) || !std::isfinite(dt)) throw std::invalid_argument("time step must be > 0 s");
  if (!(damping >= 0) || !std::isfinite(damping)) throw std::invalid_argument("damping must be >= 0 1/s");
  m_dt = dt;
  m_damping = damping;
  const double denominator = 1 + damping * dt / 2;
  for (size_t k = 0; k < m_mass.size(); ++k) m_stepScale[k] = m_mass[k] > 0 ? dt * dt / (m_mass[k] * denominator) : 0.0;
}

void TLEDModel::fixNode(int32_t node, const Vec3& displacement, unsigned axes) {
  const size_t base = kNodeStride * size_t(m_internal[node]);
  for (size_t axis = 0; axis < 3; ++axis) {
    if (!(axes & (1u << axis))) continue;
    const size_t index = base + axis;
    auto held = std::find_if(m_held.begin(), m_held.end(), [&](const HeldAxis& h) { return h.index == index; });
    if (held == m_held.end()) {
      m_held.push_back({index, displacement[axis]});
    } else {
      held->value = displacement[axis];
    }
  }
}

bool TLEDModel::isFixed(int32_t node, int axis) const {
  const size_t index = kNodeStride * size_t(m_internal[node]) + size_t(axis);
  return std::any_of(m_held.begin(), m_held.end(), [&](const HeldAxis& h) { return h.index == index; });
}

ElementStepCounts TLEDModel::forcesInto(const double* u, double* f) const {
  std::fill(f, f + vectorSize(), 0.0);
  return accumulateInternalForces(m_elements, u, f, m_isa);
}

void TLEDModel::setElementLoopIsa(ElementLoopIsa isa) {
  if (!elementLoopAvailable(isa))
    throw std::invalid_argument(std::string("this processor cannot run the element loop's ") + elementLoopName(isa) +
                                " version");
  m_isa = isa;
}

double TLEDModel::totalMass() const { return std::accumulate(m_mass.begin(), m_mass.end(), 0.0); }

void TLEDModel::internalForcesAt(std::span<const Vec3> u, std::span<Vec3> forces) const {
  std::vector<double> at(vectorSize(), 0.0), f(vectorSize(), 0.0);
  for (size_t i = 0; i < nodeCount(); ++i)
    for (size_t axis = 0; axis < 3; ++axis) at[index(int32_t(i), axis)] = u[i][axis];
  forcesInto(at.data(), f.data());
  for (size_t i = 0; i < nodeCount(); ++i) {
    const double* fi = &f[index(int32_t(i), 0)];
    forces[i] = Vec3(fi[0], fi[1], fi[2]);
  }
}

}  // namespace trephine::fem
