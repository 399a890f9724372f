// TetraBrain: point location, contact (normal and Algorithm 2), the sweep that
// keeps the proxy out, and the ray cast that aims scripted paths.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "plugins/tetra_brain/TetraBrain.h"

namespace trephine::tetra {

namespace {

// Closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Where segment p + t (q - p), t in [0, 1], crosses triangle (a, b, c), or a value > 1.
double segmentTriangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 d = q - p, e1 = b - a, e2 = c - a;
  const Vec3 h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-300) return 2.0;
  const double inv = 1.0 / det;
  const Vec3 s = p - a;
  const double u = inv * s.dot(h);
  if (u < 0 || u > 1) return 2.0;
  const Vec3 r = s.cross(e1);
  const double v = inv * d.dot(r);
  if (v < 0 || u + v > 1) return 2.0;
  const double t = inv * e2.dot(r);
  return t >= 0 && t <= 1 ? t : 2.0;
}

}  // namespace

bool TetraBrain::inside(int32_t tet, const Vec3& p) const {
  if (m_degenerate[tet]) return false;
  const TetIndices& k = m_mesh.tets[tet];
  const Vec3 &a = m_nodes[k[0]], &b = m_nodes[k[1]], &c = m_nodes[k[2]], &d = m_nodes[k[3]];
  // Barycentric coordinates as sub-volumes; all of them non-negative inside (the
  // tets are positively oriented). A point on a face is inside both tets sharing it.
  const double tolerance = -1e-12 * signedVolume(a, b, c, d);
  return signedVolume(p, b, c, d) >= tolerance && signedVolume(a, p, c, d) >= tolerance &&
         signedVolume(a, b, p, d) >= tolerance && signedVolume(a, b, c, p) >= tolerance;
}

int32_t TetraBrain::locate(const Vec3& p) const {
  // A tet holding p now had its rest box within the displacement bound of p.
  const double slack = m_displacementBound;
  auto nearBox = [&](int32_t tet) {
    const Box3& box = m_restBoxes[tet];
    return !((p.array() < box.min().array() - slack).any() || (p.array() > box.max().array() + slack).any());
  };
  if (m_queryGrowth == 0) {
    const int64_t cell = m_tetGrid.cellOf(p);
    if (cell < 0) return -1;
    for (int32_t tet : m_tetGrid.items(cell))
      if (nearBox(tet) && inside(tet, p)) return tet;  // cells list tets in increasing order: the lowest index wins
    return -1;
  }
  // Nodes moved farther than the grid's margin: every cell within the excess.
  const Vec3 e = Vec3::Constant(m_queryGrowth);
  std::array<int32_t, 3> lo, hi;
  if (!m_tetGrid.cellRange(Box3(p - e, p + e), lo, hi)) return -1;
  int32_t found = -1;
  for (int32_t k = lo[2]; k <= hi[2]; ++k)
    for (int32_t j = lo[1]; j <= hi[1]; ++j)
      for (int32_t i = lo[0]; i <= hi[0]; ++i)
        for (int32_t tet : m_tetGrid.items(m_tetGrid.cellIndex(i, j, k))) {
          if (found >= 0 && tet >= found) break;
          if (nearBox(tet) && inside(tet, p)) found = tet;
        }
  return found;
}

bool TetraBrain::locatePoints(std::span<const Vec3> points, std::span<int32_t> tets, bool stopAtFirst) const {
  bool any = false;
  if (m_queryGrowth > 0 || points.size() > m_locator.capacity()) {
    // Widened queries (nodes beyond the margin): point by point.
    for (size_t i = 0; i < points.size(); ++i) {
      tets[i] = locate(points[i]);
      if (tets[i] >= 0) {
        any = true;
        if (stopAtFirst) return true;
      }
    }
    return any;
  }
  std::fill(tets.begin(), tets.begin() + points.size(), -1);
  m_locator.group(m_tetGrid, points);
  const Vec3 slack = Vec3::Constant(m_displacementBound);
  m_locator.forEachCell([&](int64_t cell, const Box3& pointsBox, int32_t first) {
    if (any && stopAtFirst) return;
    for (int32_t tet : m_tetGrid.items(cell)) {  // increasing: the first tet found for a point is the lowest
      const Vec3 lo = m_restBoxes[tet].min() - slack, hi = m_restBoxes[tet].max() + slack;
      if ((pointsBox.max().array() < lo.array()).any() || (pointsBox.min().array() > hi.array()).any()) continue;
      for (int32_t i = first; i >= 0; i = m_locator.nextPoint(i)) {
        if (tets[i] >= 0) continue;
        const Vec3& p = points[i];
        if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any() || !inside(tet, p)) continue;
        tets[i] = tet;
        any = true;
        if (stopAtFirst) return;
      }
    }
  });
  return any;
}

std::array<double, 4> TetraBrain::barycentric(int32_t tet, const Vec3& p) const {
  const TetIndices& k = m_mesh.tets[tet];
  const Vec3 &a = m_nodes[k[0]], &b = m_nodes[k[1]], &c = m_nodes[k[2]], &d = m_nodes[k[3]];
  const double volume = signedVolume(a, b, c, d);
  if (!(std::abs(volume) > 0)) return {0.25, 0.25, 0.25, 0.25};
  std::array<double, 4> w{signedVolume(p, b, c, d) / volume, signedVolume(a, p, c, d) / volume,
                          signedVolume(a, b, p, d) / volume, signedVolume(a, b, c, p) / volume};
  // Clamp round-off just outside the tet and renormalise: the weights split a force.
  double sum = 0;
  for (double& x : w) sum += (x = std::max(0.0, x));
  if (!(sum > 0)) return {0.25, 0.25, 0.25, 0.25};
  for (double& x : w) x /= sum;
  return w;
}

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
  for (int32_t ring = 0; ring <= maxRing; ++ring) {
    if ((ring - 1) * m_faceGrid.cellSide() - slack > best) break;
    for (int32_t k = ck - ring; k <= ck + ring; ++k)
      for (int32_t j = cj - ring; j <= cj + ring; ++j)
        for (int32_t i = ci - ring; i <= ci + ring; ++i) {
          if (std::max({std::abs(i - ci), std::abs(j - cj), std::abs(k - ck)}) != ring) continue;  // shell only
          if (i < 0 || j < 0 || k < 0 || i >= dims[0] || j >= dims[1] || k >= dims[2]) continue;
          for (int32_t f : m_faceGrid.items(m_faceGrid.cellIndex(i, j, k))) {
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

size_t TetraBrain::findHits(const Pose& X_WT, std::span<const ShellPoint> shell) {
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  size_t hits = 0;
  if (d_search.is("grid")) {
    for (size_t i = 0; i < shell.size(); ++i) m_points[i] = R * shell[i].position + X_WT.position;
    const std::span<const Vec3> points(m_points.data(), shell.size());
    if (locatePoints(points, m_pointTets, false))
      for (size_t i = 0; i < shell.size(); ++i)
        if (m_pointTets[i] >= 0) m_hits[hits++] = {m_pointTets[i], int32_t(i)};
  } else {
    hits = findHitsByScan(R, X_WT.position, shell);
  }
  m_lastHits = hits;
  m_lastRotation = R;
  m_lastPosition = X_WT.position;
  m_lastShell = shell.data();
  return hits;
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
  contact = d_penetration.is("algorithm2") ? contactAlgorithm2(R, X_WT.position, shell, hits)
                                           : contactNearestFace(R, X_WT.position, shell, hits);
  contact.points = int(hits);
  int tets = 0;
  for (size_t h = 0; h < hits; ++h) tets += h == 0 || m_hits[h].tet != m_hits[h - 1].tet;
  contact.primitives = tets;
  m_maxCollidingTets = std::max<uint64_t>(m_maxCollidingTets, tets);
  return contact;
}

size_t TetraBrain::findHitsByScan(const Eigen::Matrix3d& R, const Vec3& t, std::span<const ShellPoint> shell) {
  // The thesis's search: the tetrahedra in stored order (from the first, or from
  // the last frame's first colliding one) until one whose box meets the tool's
  // box holds a shell point; then that tetrahedron and its neighbours up to two
  // rings are tested against every point. Points in other tetrahedra are missed.
  Box3 toolBox;
  for (size_t i = 0; i < shell.size(); ++i) {
    m_points[i] = R * shell[i].position + t;
    toolBox.extend(m_points[i]);
  }
  if (!toolBox.intersects(m_bounds)) return 0;
  const int32_t n = int32_t(m_mesh.tetCount());
  const int32_t start = d_search.is("previous-contact") ? m_lastFirstTet : 0;
  int32_t first = -1;
  for (int32_t s = 0; s < n && first < 0; ++s) {
    const int32_t tet = (start + s) % n;
    ++m_scannedTets;
    if (!m_tetBoxes[tet].intersects(toolBox)) continue;
    for (size_t i = 0; i < shell.size(); ++i) {
      if (m_tetBoxes[tet].contains(m_points[i]) && inside(tet, m_points[i])) {
        first = tet;
        break;
      }
    }
  }
  if (first < 0) return 0;
  m_lastFirstTet = first;
  // Two rings of face neighbours, without repeats (a handful of tets: a linear check suffices).
  size_t count = 0;
  m_candidates[count++] = first;
  size_t ringStart = 0;
  for (int ring = 0; ring < 2; ++ring) {
    const size_t ringEnd = count;
    for (size_t c = ringStart; c < ringEnd; ++c)
      for (int f = 0; f < 4; ++f) {
        const int32_t nb = m_topology.neighbour(m_candidates[c], f);
        if (nb < 0 || std::find(m_candidates.begin(), m_candidates.begin() + count, nb) != m_candidates.begin() + count)
          continue;
        m_candidates[count++] = nb;
      }
    ringStart = ringEnd;
  }
  std::sort(m_candidates.begin(), m_candidates.begin() + count);
  size_t hits = 0;
  for (size_t i = 0; i < shell.size(); ++i)
    for (size_t c = 0; c < count; ++c)
      if (m_tetBoxes[m_candidates[c]].contains(m_points[i]) && inside(m_candidates[c], m_points[i])) {
        m_hits[hits++] = {m_candidates[c], int32_t(i)};
        break;
      }
  return hits;
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
        m_nodeForceValue.forces[slot] = {k[i], Vec3::Zero()};
      }
      m_nodeForceValue.forces[slot].force += (share * w[i]) * forceOnTarget_N;
    }
  }
  for (uint32_t i = 0; i < count; ++i) m_nodeSlot[m_nodeForceValue.forces[i].node] = -1;
  m_nodeForceValue.count = count;
  m_nodeForceValue.t = t;
  m_nodeForces->publish(m_nodeForceValue);
}

bool TetraBrain::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  // Visible overlap: the tool's centre, or its shell pulled inwards by ten contact
  // depths, is inside the mesh.
  if (locate(X_WT.position) >= 0) return true;
  const Box3 grown(m_bounds.min() - Vec3::Constant(1.0), m_bounds.max() + Vec3::Constant(1.0));
  if (!grown.contains(X_WT.position)) {
    double radius = 0;
    for (const ShellPoint& p : shell) radius = std::max(radius, p.position.norm());
    if (grown.exteriorDistance(X_WT.position) > radius) return false;
  }
  const double inset = 10 * d_contactDepth.value();
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  if (shell.size() > m_insetPoints.size()) return false;  // not a reserved shell
  for (size_t i = 0; i < shell.size(); ++i) {
    const double pull = std::min(inset, shell[i].position.norm());
    m_insetPoints[i] = R * (shell[i].position + pull * shell[i].inwardNormal) + X_WT.position;
  }
  return locatePoints({m_insetPoints.data(), shell.size()}, m_insetTets, true);
}

double TetraBrain::firstEntry(const Vec3& a, const Vec3& b, bool skipInitialInside, bool& startsInside) const {
  startsInside = locate(a) >= 0;
  if (startsInside && !skipInitialInside) return 0.0;
  // Boundary faces in the cells the segment's box covers; the first crossing
  // from outside to inside (moving against the face's outward normal).
  Box3 box;
  box.extend(a);
  box.extend(b);
  box = Box3(box.min() - Vec3::Constant(m_queryGrowth), box.max() + Vec3::Constant(m_queryGrowth));
  std::array<int32_t, 3> lo, hi;
  if (!m_faceGrid.cellRange(box, lo, hi)) return 2.0;
  const auto& faces = m_topology.boundaryFaces();
  const Vec3 direction = b - a;
  double first = 2.0;
  for (int32_t k = lo[2]; k <= hi[2]; ++k)
    for (int32_t j = lo[1]; j <= hi[1]; ++j)
      for (int32_t i = lo[0]; i <= hi[0]; ++i)
        for (int32_t f : m_faceGrid.items(m_faceGrid.cellIndex(i, j, k))) {
          const Vec3 n = faceNormal(faces[f]);
          if (direction.dot(n) >= 0) continue;  // leaving, or grazing
          const auto v = faceNodes(m_mesh.tets[faces[f].tet], faces[f].face);
          const double t = segmentTriangle(a, b, m_nodes[v[0]], m_nodes[v[1]], m_nodes[v[2]]);
          if (t < first && !(startsInside && t == 0)) first = t;
        }
  return first;
}

SweepResult TetraBrain::sweep(const SweepQuery& query) const {
  SweepResult result;
  const Vec3 path = query.to - query.from;
  const double length = path.norm();
  if (!(length > 0) || !std::isfinite(length)) return result;
  const Vec3 u = path / length;
  const bool buried = locate(query.from) >= 0;
  auto probe = [&](const Vec3& offset, bool blockAtStart) {
    bool startsInside = false;
    const double t = firstEntry(query.from + offset, query.to + offset, buried || !blockAtStart, startsInside);
    if (startsInside && blockAtStart && !buried) {
      result.blocked = result.startsInside = true;
      result.freeFraction = 0;
      result.contactPoint = query.from + offset;
      return true;
    }
    if (t <= 1.0 && (!result.blocked || t < result.freeFraction)) {
      result.blocked = true;
      result.freeFraction = t;
      result.contactPoint = query.from + offset + t * path;
    }
    return false;
  };
  const double R = query.leadingRadius;
  if (probe(R * u, true)) return result;
  if (query.probe != SweepProbe::Line && R > 0) {
    // Cylinder (and, here, spheres): lines from rings on the front hemisphere.
    const Vec3 helper = std::abs(u.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    const Vec3 e1 = u.cross(helper).normalized(), e2 = u.cross(e1);
    for (const double ahead : {0.866, 0.5, 0.0}) {
      const double r = R * std::sqrt(1.0 - ahead * ahead);
      const int count = std::max(6, int(std::ceil(2 * std::numbers::pi * r / std::max(0.25, 0.5 * m_averageEdge))));
      for (int i = 0; i < count; ++i) {
        const double phi = 2 * std::numbers::pi * i / count;
        if (probe(r * (std::cos(phi) * e1 + std::sin(phi) * e2) + ahead * R * u, ahead > 0)) return result;
      }
    }
  }
  return result;
}

std::optional<SurfaceHit> TetraBrain::raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const {
  bool startsInside = false;
  const Vec3 end = origin + maxDistance * direction;
  const double t = firstEntry(origin, end, false, startsInside);
  if (startsInside) return SurfaceHit{origin, -direction, 0.0};
  if (t > 1.0) return std::nullopt;
  SurfaceHit hit;
  hit.distance = t * maxDistance;
  hit.point = origin + hit.distance * direction;
  Vec3 normal;
  depthBelowSurface(hit.point, normal);
  hit.normal = normal.squaredNorm() > 0.5 ? normal : Vec3(-direction);
  return hit;
}

}  // namespace trephine::tetra
