// TetraBrain: contact normal and penetration of the colliding points (nearest
// boundary face, or the thesis's Algorithm 2), depth below the surface, and the
// reaction of the contact force on the nodes.
#include <algorithm>
#include <cmath>
#include <limits>

#include "framework/geometry/ClosestPoint.h"
#include "plugins/tetra_brain/TetraBrain.h"

namespace trephine::tetra {

Vec3 TetraBrain::faceNormal(const BoundaryFace& face) const {
  const auto n = faceNodes(m_mesh.tets[face.tet], face.face);
  const Vec3 normal = (m_nodes[n[1]] - m_nodes[n[0]]).cross(m_nodes[n[2]] - m_nodes[n[0]]);
  const double length = normal.norm();
  return length > 0 ? Vec3(normal / length) : Vec3::Zero();
}

double TetraBrain::depthToIncidentFaces(int32_t tet, const Vec3& p, Vec3& normal) const {
  // A tet that touches the surface only at a node or an edge: the nearest of
  // the boundary faces around its nodes (a handful), instead of a search of
  // the whole neighbourhood. Infinite when no node of the tet is on the surface.
  double best = std::numeric_limits<double>::infinity();
  const auto& faces = m_topology.boundaryFaces();
  for (int32_t node : m_mesh.tets[tet]) {
    for (uint32_t e = m_nodeFaceStart[node]; e < m_nodeFaceStart[node + 1]; ++e) {
      const BoundaryFace& face = faces[m_nodeFaces[e]];
      const auto n = faceNodes(m_mesh.tets[face.tet], face.face);
      const double distance = (closestOnTriangle(p, m_nodes[n[0]], m_nodes[n[1]], m_nodes[n[2]]) - p).norm();
      if (distance < best) {
        best = distance;
        normal = faceNormal(face);
      }
    }
  }
  return best;
}

double TetraBrain::depthBelowSurface(const Vec3& p, Vec3& normal) const {
  // Rings of cells around p, nearest first, until no closer face can remain.
  const Vec3 g = (p - m_faceGrid.origin()) / m_faceGrid.cellSide();
  const auto& dims = m_faceGrid.dims();
  // Faces sit in the cells of their rest boxes grown by the margin: a face may
  // be up to the excess of the displacement bound farther than its cells say,
  // and a point outside the grid is that much farther from every cell.
  const Vec3 lo = m_faceGrid.origin();
  const Vec3 hi = lo + m_faceGrid.cellSide() * Vec3(dims[0], dims[1], dims[2]);
  const double outside = (lo - p).cwiseMax(p - hi).cwiseMax(0.0).maxCoeff();
  const double slack = m_queryGrowth + outside;
  const int32_t ci = std::clamp(int32_t(std::floor(g.x())), 0, dims[0] - 1);
  const int32_t cj = std::clamp(int32_t(std::floor(g.y())), 0, dims[1] - 1);
  const int32_t ck = std::clamp(int32_t(std::floor(g.z())), 0, dims[2] - 1);
  double best = std::numeric_limits<double>::infinity();
  normal.setZero();
  const int32_t maxRing = std::max({dims[0], dims[1], dims[2]});
  const auto& faces = m_topology.boundaryFaces();
  m_faceVisits.begin();
  for (int32_t ring = 0; ring <= maxRing; ++ring) {
    if ((ring - 1) * m_faceGrid.cellSide() - slack > best) break;
    for (int32_t k = ck - ring; k <= ck + ring; ++k)
      for (int32_t j = cj - ring; j <= cj + ring; ++j)
        for (int32_t i = ci - ring; i <= ci + ring; ++i) {
          if (std::max({std::abs(i - ci), std::abs(j - cj), std::abs(k - ck)}) != ring) continue;  // shell only
          if (i < 0 || j < 0 || k < 0 || i >= dims[0] || j >= dims[1] || k >= dims[2]) continue;
          for (int32_t f : m_faceGrid.items(m_faceGrid.cellIndex(i, j, k))) {
            if (!m_faceVisits.firstVisit(f)) continue;
            const auto n = faceNodes(m_mesh.tets[faces[f].tet], faces[f].face);
            const Vec3 q = closestOnTriangle(p, m_nodes[n[0]], m_nodes[n[1]], m_nodes[n[2]]);
            const double distance = (q - p).norm();
            if (distance < best) {
              best = distance;
              normal = faceNormal(faces[f]);
            }
          }
        }
  }
  return std::isfinite(best) ? best : 0.0;
}

ShellContact TetraBrain::collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool) {
  ShellContact contact;
  if (std::find(m_shells.begin(), m_shells.end(), shell.data()) == m_shells.end()) {
    ++m_unreservedShellCalls;
    return contact;
  }
  return contactOfHits(shell, findHits(X_WT, shell));
}

ShellContact TetraBrain::contactOfHits(std::span<const ShellPoint> shell, size_t hits) {
  ShellContact contact;
  const Eigen::Matrix3d& R = m_lastRotation;
  const Pose X_WT{m_lastPosition, Quat::Identity()};  // only the position is read below
  if (hits == 0) return contact;
  ++m_contactFrames;
  std::sort(m_hits.begin(), m_hits.begin() + hits,
            [](const Hit& a, const Hit& b) { return a.tet < b.tet || (a.tet == b.tet && a.point < b.point); });
  contact = m_algorithm2 ? contactAlgorithm2(R, X_WT.position, shell, hits)
                         : contactNearestFace(R, X_WT.position, shell, hits);
  contact.points = int(hits);
  int tets = 0;
  for (size_t h = 0; h < hits; ++h) tets += h == 0 || m_hits[h].tet != m_hits[h - 1].tet;
  contact.primitives = tets;
  m_maxCollidingTets = std::max<uint64_t>(m_maxCollidingTets, tets);
  return contact;
}

ShellContact TetraBrain::contactNearestFace(const Eigen::Matrix3d& R, const Vec3& t, std::span<const ShellPoint> shell,
                                            size_t hits) {
  // Each colliding point measures to the nearest boundary face of its tet (the
  // plane it entered through), or, when its tet has none, to the nearest
  // boundary face of the mesh.
  ShellContact contact;
  Vec3 weighted = Vec3::Zero(), plain = Vec3::Zero();
  for (size_t h = 0; h < hits; ++h) {
    const int32_t tet = m_hits[h].tet;
    const Vec3 p = R * shell[m_hits[h].point].position + t;
    const uint8_t mask = m_topology.boundaryMask(tet);
    double depth = std::numeric_limits<double>::infinity();
    Vec3 normal = Vec3::Zero();
    for (int f = 0; f < 4; ++f) {
      if (!(mask & (1u << f))) continue;
      const Vec3 n = faceNormal({tet, int8_t(f)});
      const double d = (m_nodes[faceNodes(m_mesh.tets[tet], f)[0]] - p).dot(n);
      if (d < depth) depth = d, normal = n;
    }
    if (!std::isfinite(depth)) depth = depthToIncidentFaces(tet, p, normal);
    if (!std::isfinite(depth)) {
      ++m_deepFallbacks;
      depth = depthBelowSurface(p, normal);
    }
    depth = std::max(0.0, depth);
    m_depths[h] = depth;
    m_normals[h] = normal;
    weighted += depth * normal;
    plain += normal;
  }
  const double wl = weighted.norm(), pl = plain.norm();
  if (wl > 1e-12) {
    contact.normal = weighted / wl;
  } else if (pl > 1e-9) {
    contact.normal = plain / pl;
  }
  for (size_t h = 0; h < hits; ++h)
    contact.penetration = std::max(contact.penetration, m_depths[h] * std::max(0.0, m_normals[h].dot(contact.normal)));
  return contact;
}

ShellContact TetraBrain::contactAlgorithm2(const Eigen::Matrix3d& R, const Vec3& t, std::span<const ShellPoint> shell,
                                           size_t hits) {
  // The normal averages the unit outward normals of the colliding tets'
  // boundary faces; the penetration is the largest distance of a colliding point
  // to the plane of one of the boundary faces of its tet (Algorithm 2).
  ShellContact contact;
  Vec3 normalSum = Vec3::Zero();
  double penetration = 0;
  int faceCount = 0;
  std::fill(m_depths.begin(), m_depths.begin() + hits, 0.0);  // per point, for the nodal force shares
  for (size_t first = 0; first < hits;) {
    size_t last = first;
    while (last < hits && m_hits[last].tet == m_hits[first].tet) ++last;
    const int32_t tet = m_hits[first].tet;
    const uint8_t mask = m_topology.boundaryMask(tet);
    for (int f = 0; f < 4; ++f) {
      if (!(mask & (1u << f))) continue;
      const Vec3 n = faceNormal({tet, int8_t(f)});
      normalSum += n;
      ++faceCount;
      const Vec3& onFace = m_nodes[faceNodes(m_mesh.tets[tet], f)[0]];
      for (size_t h = first; h < last; ++h) {
        m_depths[h] = std::max(m_depths[h], std::abs((onFace - (R * shell[m_hits[h].point].position + t)).dot(n)));
        penetration = std::max(penetration, m_depths[h]);
      }
    }
    first = last;
  }
  const double length = normalSum.norm();
  if (faceCount == 0 || length < 1e-3 * faceCount) {
    // No boundary face among the colliding tets (the tool deep in the mesh), or
    // their normals cancel (a sharp ridge): the nearest boundary face instead.
    ++m_deepFallbacks;
    double depth = 0;
    Vec3 normal = Vec3::Zero();
    for (size_t h = 0; h < hits; ++h) {
      Vec3 candidate;
      const double d = depthBelowSurface(R * shell[m_hits[h].point].position + t, candidate);
      if (d > depth) depth = d, normal = candidate;
    }
    contact.normal = normal;
    contact.penetration = depth;
  } else {
    contact.normal = normalSum / length;
    contact.penetration = penetration;
  }
  return contact;
}

void TetraBrain::applyContactForce(const Vec3& forceOnTarget_N, double t) {
  // The reaction on the mesh: shared among the colliding points by depth (the
  // points that press hardest carry most), then to the four nodes of each
  // point's tet by its barycentric coordinates, so that the nodal forces sum to
  // the contact force and act where it acts. Computed only for a reader.
  if (m_nodeSlot.empty() || m_lastHits == 0 || !forceOnTarget_N.allFinite()) return;
  double depthSum = 0;
  for (size_t h = 0; h < m_lastHits; ++h) depthSum += m_depths[h];
  std::vector<NodeForce>& forces = m_nodeForceValue.forces;
  forces.resize(4 * m_lastHits);  // within the capacity reserveShell() gave it: no allocation
  uint32_t count = 0;
  for (size_t h = 0; h < m_lastHits; ++h) {
    const double share = depthSum > 0 ? m_depths[h] / depthSum : 1.0 / double(m_lastHits);
    if (share == 0) continue;
    const Vec3 p = m_lastRotation * m_lastShell[m_hits[h].point].position + m_lastPosition;
    const std::array<double, 4> w = barycentric(m_hits[h].tet, p);
    const TetIndices& k = m_mesh.tets[m_hits[h].tet];
    for (int i = 0; i < 4; ++i) {
      int32_t& slot = m_nodeSlot[k[i]];
      if (slot < 0) {
        slot = int32_t(count++);
        forces[slot] = {k[i], Vec3::Zero()};
      }
      forces[slot].force += (share * w[i]) * forceOnTarget_N;
    }
  }
  forces.resize(count);
  for (const NodeForce& f : forces) m_nodeSlot[f.node] = -1;
  m_nodeForceValue.t = t;
  m_nodeForces->publish(m_nodeForceValue);
}

}  // namespace trephine::tetra
