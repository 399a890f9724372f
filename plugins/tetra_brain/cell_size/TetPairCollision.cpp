#include "plugins/tetra_brain/cell_size/TetPairCollision.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace trephine::tetra {

PairCounts& PairCounts::operator+=(const PairCounts& o) {
  cellVisits += o.cellVisits;
  boxTests += o.boxTests;
  barycentricTests += o.barycentricTests;
  contacts += o.contacts;
  tetsWithParticles += o.tetsWithParticles;
  collidingTets += o.collidingTets;
  return *this;
}

void ParticleGrid::build(std::span<const Vec3> points, const Box3& bounds, double cellSize, size_t maxCells) {
  if (!(cellSize > 0) || bounds.isEmpty()) throw std::invalid_argument("a grid needs a positive cell size and bounds");
  m_origin = bounds.min();
  m_side = cellSize;
  size_t cells = 1;
  for (int a = 0; a < 3; ++a) {
    const double n = std::max(1.0, std::ceil(bounds.sizes()[a] / cellSize));
    if (n > double(maxCells)) throw std::invalid_argument("cell size " + std::to_string(cellSize) + " mm: too many cells");
    m_dims[a] = int32_t(n);
    cells *= size_t(n);
    if (cells > maxCells)
      throw std::invalid_argument("cell size " + std::to_string(cellSize) + " mm needs more than " +
                                  std::to_string(maxCells) + " cells");
  }
  // Counting sort: the count of each cell, its start, then the particles.
  m_start.assign(cells + 1, 0);
  m_cellOf.resize(points.size());
  const double inverse = 1 / cellSize;
  for (size_t p = 0; p < points.size(); ++p) {
    const Vec3 g = (points[p] - m_origin) * inverse;
    int32_t c[3];
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      c[a] = int32_t(std::floor(g[a]));
      if (c[a] == m_dims[a] && g[a] <= double(m_dims[a])) c[a] = m_dims[a] - 1;  // on the far face
      inside = inside && c[a] >= 0 && c[a] < m_dims[a];
    }
    m_cellOf[p] = inside ? int32_t(size_t(c[0]) + size_t(m_dims[0]) * (size_t(c[1]) + size_t(m_dims[1]) * size_t(c[2])))
                         : -1;
    if (inside) ++m_start[size_t(m_cellOf[p]) + 1];
  }
  for (size_t c = 0; c < cells; ++c) m_start[c + 1] += m_start[c];
  m_items.resize(m_start[cells]);
  for (size_t p = 0; p < points.size(); ++p)
    if (m_cellOf[p] >= 0) m_items[m_start[size_t(m_cellOf[p])]++] = int32_t(p);
  // The starts were advanced to the ends: shift them back.
  for (size_t c = cells; c > 0; --c) m_start[c] = m_start[c - 1];
  m_start[0] = 0;
}

bool ParticleGrid::cellRange(const Box3& box, std::array<int32_t, 3>& lo, std::array<int32_t, 3>& hi) const {
  for (int a = 0; a < 3; ++a) {
    const double l = std::floor((box.min()[a] - m_origin[a]) / m_side);
    const double h = std::floor((box.max()[a] - m_origin[a]) / m_side);
    if (h < 0 || l >= m_dims[a]) return false;
    lo[a] = int32_t(std::max(0.0, l));
    hi[a] = int32_t(std::min(double(m_dims[a] - 1), h));
  }
  return true;
}

PairCounts findParticlesInTets(std::span<const Vec3> nodes, std::span<const TetIndices> tets,
                               std::span<const Vec3> particles, const ParticleGrid& grid, std::vector<Box3>& boxes,
                               std::vector<ParticleInTet>& found) {
  PairCounts counts;
  // First pass: the boxes on the current nodes.
  boxes.resize(tets.size());
  for (size_t t = 0; t < tets.size(); ++t) {
    Box3 box;
    for (int32_t n : tets[t]) box.extend(nodes[n]);
    boxes[t] = box;
  }
  // Second pass: objective voxels, their particles, the box, the tetrahedron.
  for (size_t t = 0; t < tets.size(); ++t) {
    std::array<int32_t, 3> lo, hi;
    if (!grid.cellRange(boxes[t], lo, hi)) continue;
    const Box3& box = boxes[t];
    const Vec3 &a = nodes[tets[t][0]], &b = nodes[tets[t][1]], &c = nodes[tets[t][2]], &d = nodes[tets[t][3]];
    const double volume = signedVolume(a, b, c, d);
    bool anyParticle = false, anyContact = false;
    for (int32_t k = lo[2]; k <= hi[2]; ++k)
      for (int32_t j = lo[1]; j <= hi[1]; ++j)
        for (int32_t i = lo[0]; i <= hi[0]; ++i) {
          ++counts.cellVisits;
          for (int32_t p : grid.particles(i, j, k)) {
            anyParticle = true;
            ++counts.boxTests;
            const Vec3& x = particles[p];
            if (!box.contains(x)) continue;
            ++counts.barycentricTests;
            if (volume == 0) continue;
            const double w[4] = {signedVolume(x, b, c, d) / volume, signedVolume(a, x, c, d) / volume,
                                 signedVolume(a, b, x, d) / volume, signedVolume(a, b, c, x) / volume};
            if (w[0] < 0 || w[1] < 0 || w[2] < 0 || w[3] < 0) continue;
            found.push_back({p, int32_t(t), {w[0], w[1], w[2], w[3]}});
            ++counts.contacts;
            anyContact = true;
          }
        }
    counts.tetsWithParticles += anyParticle;
    counts.collidingTets += anyContact;
  }
  return counts;
}

TetPairScene::TetPairScene(const TetMesh& a, const TetMesh& b, const Vec3& offsetOfB)
    : m_a(a), m_b(b), m_offsetB(offsetOfB) {
  m_nodesA.resize(a.nodes.size());
  m_particlesB.resize(b.nodes.size());
  for (size_t i = 0; i < a.nodes.size(); ++i) m_nodesA[i] = a.nodes[i];
  for (size_t i = 0; i < b.nodes.size(); ++i) m_particlesB[i] = b.nodes[i] + offsetOfB;
  m_found.reserve(b.nodes.size());
}

PairCounts TetPairScene::detect(double cellSize) {
  Box3 bounds;
  for (const Vec3& p : m_nodesA) bounds.extend(p);
  for (const Vec3& p : m_particlesB) bounds.extend(p);
  m_grid.build(m_particlesB, bounds, cellSize);
  m_found.clear();
  return findParticlesInTets(m_nodesA, m_a.tets, m_particlesB, m_grid, m_boxes, m_found);
}

PairCounts TetPairScene::step(double cellSize, double dt) {
  const PairCounts counts = detect(cellSize);
  // Penalty on rigid bodies: each particle inside pushes B away from A along
  // the line of their centres, in proportion to its depth, taken as its
  // distance to the nearest facet of its tetrahedron (lambda_i / |grad
  // lambda_i|, a lower bound of the depth below A's surface).
  Vec3 centreA = Vec3::Zero(), centreB = Vec3::Zero();
  for (const Vec3& p : m_nodesA) centreA += p;
  for (const Vec3& p : m_particlesB) centreB += p;
  centreA /= double(std::max<size_t>(1, m_nodesA.size()));
  centreB /= double(std::max<size_t>(1, m_particlesB.size()));
  const Vec3 apart = (centreB - centreA).norm() > 0 ? Vec3((centreB - centreA).normalized()) : Vec3::UnitX();
  double depthSum = 0;  // mm
  for (const ParticleInTet& f : m_found) {
    const TetIndices& t = m_a.tets[f.tet];
    Eigen::Matrix3d D;
    for (int k = 0; k < 3; ++k) D.col(k) = m_nodesA[t[k + 1]] - m_nodesA[t[0]];
    const Eigen::Matrix3d inverse = D.inverse();
    Vec3 gradient[4];
    for (int k = 0; k < 3; ++k) gradient[k + 1] = inverse.row(k).transpose();
    gradient[0] = -(gradient[1] + gradient[2] + gradient[3]);
    double depth = INFINITY;
    for (int k = 0; k < 4; ++k) depth = std::min(depth, f.weights[k] / gradient[k].norm());
    depthSum += depth;
  }
  const Vec3 force = stiffness * depthSum * apart;  // N, on B
  // Rigid translations, symplectic Euler; N/kg = 1000 mm/s^2.
  m_velocityB += 1000 * force / massB * dt;
  m_velocityA -= 1000 * force / massA * dt;
  const Vec3 moveA = m_velocityA * dt, moveB = m_velocityB * dt;
  m_offsetA += moveA;
  m_offsetB += moveB;
  for (Vec3& p : m_nodesA) p += moveA;
  for (Vec3& p : m_particlesB) p += moveB;
  return counts;
}

}  // namespace trephine::tetra
