// NativeTetBackend: contact normal and penetration of the colliding points (nearest
// boundary face, or the thesis's Algorithm 2), depth below the surface, and the
// sites where the contact presses on the nodes.
#include <algorithm>
#include <cmath>
#include <limits>

#include "framework/geometry/ClosestPoint.h"
#include "plugins/tetra_brain/NativeTetBackend.h"

namespace trephine::tetra {

namespace {

// The nearest of the faces offered. Faces as near as the nearest within
// round-off (a point nearest an edge or a node of the surface is as near
// several faces) go to the lowest (tetrahedron, face): the answer then does
// not depend on the order the faces are visited in, which the grid's cells
// and a removal change.
struct NearestFace {
  double distance = std::numeric_limits<double>::infinity();
  BoundaryFace face{-1, 0};
  bool found() const { return face.tet >= 0; }
  void offer(double d, const BoundaryFace& candidate) {
    const double tie = 1e-12 * (1.0 + d);
    if (d < distance - tie || (d <= distance + tie && key(candidate) < key(face))) {
      if (d < distance) distance = d;
      face = candidate;
    }
  }
  static int64_t key(const BoundaryFace& f) { return f.tet < 0 ? INT64_MAX : int64_t(f.tet) * 4 + f.face; }
};

}  // namespace

Vec3 NativeTetBackend::faceNormal(const BoundaryFace& face) const {
  const auto n = faceNodes(m_mesh->tets[face.tet], face.face);
  const Vec3 normal = (m_nodes[n[1]] - m_nodes[n[0]]).cross(m_nodes[n[2]] - m_nodes[n[0]]);
  const double length = normal.norm();
  return length > 0 ? Vec3(normal / length) : Vec3::Zero();
}

double NativeTetBackend::depthToIncidentFaces(int32_t tet, const Vec3& p, Vec3& normal) const {
  // A tet that touches the surface only at a node or an edge: the nearest of
  // the boundary faces around its nodes (a handful), instead of a search of
  // the whole neighbourhood. Infinite when no node of the tet is on the surface.
  NearestFace nearest;
  for (int32_t node : m_mesh->tets[tet]) {
    for (int32_t slot : m_live.aroundNode(node)) {
      const BoundaryFace face = LiveFaces::faceOf(slot);
      const auto n = faceNodes(m_mesh->tets[face.tet], face.face);
      nearest.offer((closestOnTriangle(p, m_nodes[n[0]], m_nodes[n[1]], m_nodes[n[2]]) - p).norm(), face);
    }
  }
  if (nearest.found()) normal = faceNormal(nearest.face);
  return nearest.distance;
}

double NativeTetBackend::depthBelowSurface(const Vec3& p, Vec3& normal) const {
  // Rings of cells around p, nearest first, until no closer face can remain.
  const Vec3 g = (p - m_grids->faceGrid.origin()) / m_grids->faceGrid.cellSide();
  const auto& dims = m_grids->faceGrid.dims();
  // Faces sit in the cells of their rest boxes grown by the margin: a face may
  // be up to the excess of the displacement bound farther than its cells say,
  // and a point outside the grid is that much farther from every cell.
  const Vec3 lo = m_grids->faceGrid.origin();
  const Vec3 hi = lo + m_grids->faceGrid.cellSide() * Vec3(dims[0], dims[1], dims[2]);
  const double outside = (lo - p).cwiseMax(p - hi).cwiseMax(0.0).maxCoeff();
  const double slack = m_queryGrowth + outside;
  const int32_t ci = std::clamp(int32_t(std::floor(g.x())), 0, dims[0] - 1);
  const int32_t cj = std::clamp(int32_t(std::floor(g.y())), 0, dims[1] - 1);
  const int32_t ck = std::clamp(int32_t(std::floor(g.z())), 0, dims[2] - 1);
  NearestFace nearest;
  normal.setZero();
  // The cavity's faces (a resection's), a list; then the first boundary's, by rings.
  for (const BoundaryFace& face : m_live.exposed()) {
    const auto n = faceNodes(m_mesh->tets[face.tet], face.face);
    nearest.offer((closestOnTriangle(p, m_nodes[n[0]], m_nodes[n[1]], m_nodes[n[2]]) - p).norm(), face);
  }
  const int32_t maxRing = std::max({dims[0], dims[1], dims[2]});
  const auto faces = this->faces();
  m_faceVisits.begin();
  for (int32_t ring = 0; ring <= maxRing; ++ring) {
    if ((ring - 1) * m_grids->faceGrid.cellSide() - slack > nearest.distance) break;
    for (int32_t k = std::max(0, ck - ring); k <= std::min(dims[2] - 1, ck + ring); ++k)
      for (int32_t j = std::max(0, cj - ring); j <= std::min(dims[1] - 1, cj + ring); ++j) {
        // The ring's shell only: a whole row where j or k is on it, else its two ends.
        const bool wholeRow = std::abs(k - ck) == ring || std::abs(j - cj) == ring;
        const int32_t step = wholeRow ? 1 : std::max(1, 2 * ring);
        for (int32_t i = ci - ring; i <= ci + ring; i += step) {
          if (i < 0 || i >= dims[0]) continue;
          for (int32_t f : m_grids->faceGrid.items(m_grids->faceGrid.cellIndex(i, j, k))) {
            if (!m_faceVisits.firstVisit(f) || !m_live.onBoundary(faces[f])) continue;
            const auto n = faceNodes(m_mesh->tets[faces[f].tet], faces[f].face);
            nearest.offer((closestOnTriangle(p, m_nodes[n[0]], m_nodes[n[1]], m_nodes[n[2]]) - p).norm(), faces[f]);
          }
        }
      }
  }
  if (!nearest.found()) return 0.0;
  normal = faceNormal(nearest.face);
  return nearest.distance;
}

bool NativeTetBackend::surfaceWithin(const Vec3& p, double radius) const {
  // A face within `radius` of p now had its grids' box within radius plus
  // the displacement bound of p; the cells hold the boxes grown by the
  // margin, so the cells within radius plus the excess hold it.
  const Vec3 reach = Vec3::Constant(radius + m_queryGrowth);
  const auto faces = this->faces();
  const Box3 ball(p - Vec3::Constant(radius), p + Vec3::Constant(radius));
  auto within = [&](const BoundaryFace& f) {
    const auto n = faceNodes(m_mesh->tets[f.tet], f.face);
    const Vec3 &a = m_nodes[n[0]], &b = m_nodes[n[1]], &c = m_nodes[n[2]];
    const Box3 face(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c));
    return face.intersects(ball) && (closestOnTriangle(p, a, b, c) - p).squaredNorm() <= radius * radius;
  };
  for (const BoundaryFace& f : m_live.exposed())
    if (within(f)) return true;
  return anyFaceInCells(Box3(p - reach, p + reach),
                        [&](int32_t f) { return m_live.onBoundary(faces[f]) && within(faces[f]); });
}

TetContact NativeTetBackend::collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool wantSites,
                                     int32_t& searchStart) {
  return contactOfHits(X_WT, shell, findHits(X_WT, shell, searchStart), wantSites);
}

TetContact NativeTetBackend::contactOfHits(const Pose& X_WT, std::span<const ShellPoint> shell, std::span<TetHit> hits,
                                           bool wantSites) {
  TetContact result;
  if (hits.empty()) return result;
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  std::sort(hits.begin(), hits.end(),
            [](const TetHit& a, const TetHit& b) { return a.tet < b.tet || (a.tet == b.tet && a.point < b.point); });
  ShellContact& contact = result.contact;
  contact = m_options.algorithm2 ? contactAlgorithm2(R, X_WT.position, shell, hits)
                                 : contactNearestFace(R, X_WT.position, shell, hits);
  contact.points = int(hits.size());
  int tets = 0;
  for (size_t h = 0; h < hits.size(); ++h)
    if (h == 0 || hits[h].tet != hits[h - 1].tet) m_hitTets[size_t(tets++)] = hits[h].tet;
  contact.primitives = tets;
  result.tets = {m_hitTets.data(), size_t(tets)};
  m_maxCollidingTets = std::max<uint64_t>(m_maxCollidingTets, tets);
  if (wantSites) {
    // Each colliding point presses on its tetrahedron's nodes by its
    // barycentric coordinates (current nodes), as deep as it measured.
    for (size_t h = 0; h < hits.size(); ++h) {
      const Vec3 p = R * shell[hits[h].point].position + X_WT.position;
      m_sites[h] = {m_mesh->tets[hits[h].tet], barycentric(hits[h].tet, p), m_depths[h]};
    }
    result.sites = {m_sites.data(), hits.size()};
  }
  return result;
}

ShellContact NativeTetBackend::contactNearestFace(const Eigen::Matrix3d& R, const Vec3& t,
                                                  std::span<const ShellPoint> shell, std::span<const TetHit> hits) {
  // Each colliding point measures to the nearest boundary face of its tet (the
  // plane it entered through), or, when its tet has none, to the nearest
  // boundary face of the mesh.
  ShellContact contact;
  Vec3 weighted = Vec3::Zero(), plain = Vec3::Zero();
  for (size_t h = 0; h < hits.size(); ++h) {
    const int32_t tet = hits[h].tet;
    const Vec3 p = R * shell[hits[h].point].position + t;
    const uint8_t mask = m_live.mask(tet);
    double depth = std::numeric_limits<double>::infinity();
    Vec3 normal = Vec3::Zero();
    for (int f = 0; f < 4; ++f) {
      if (!(mask & (1u << f))) continue;
      const Vec3 n = faceNormal({tet, int8_t(f)});
      const double d = (m_nodes[faceNodes(m_mesh->tets[tet], f)[0]] - p).dot(n);
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
  for (size_t h = 0; h < hits.size(); ++h)
    contact.penetration = std::max(contact.penetration, m_depths[h] * std::max(0.0, m_normals[h].dot(contact.normal)));
  return contact;
}

ShellContact NativeTetBackend::contactAlgorithm2(const Eigen::Matrix3d& R, const Vec3& t,
                                                 std::span<const ShellPoint> shell, std::span<const TetHit> hits) {
  // The normal averages the unit outward normals of the colliding tets'
  // boundary faces; the penetration is the largest distance of a colliding point
  // to the plane of one of the boundary faces of its tet (Algorithm 2).
  ShellContact contact;
  Vec3 normalSum = Vec3::Zero();
  double penetration = 0;
  int faceCount = 0;
  std::fill(m_depths.begin(), m_depths.begin() + hits.size(), 0.0);  // per point, for the nodal force shares
  for (size_t first = 0; first < hits.size();) {
    size_t last = first;
    while (last < hits.size() && hits[last].tet == hits[first].tet) ++last;
    const int32_t tet = hits[first].tet;
    const uint8_t mask = m_live.mask(tet);
    for (int f = 0; f < 4; ++f) {
      if (!(mask & (1u << f))) continue;
      const Vec3 n = faceNormal({tet, int8_t(f)});
      normalSum += n;
      ++faceCount;
      const Vec3& onFace = m_nodes[faceNodes(m_mesh->tets[tet], f)[0]];
      for (size_t h = first; h < last; ++h) {
        m_depths[h] = std::max(m_depths[h], std::abs((onFace - (R * shell[hits[h].point].position + t)).dot(n)));
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
    for (size_t h = 0; h < hits.size(); ++h) {
      Vec3 candidate;
      const double d = depthBelowSurface(R * shell[hits[h].point].position + t, candidate);
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

}  // namespace trephine::tetra
