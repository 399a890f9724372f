// NativeTetBackend: which tetrahedron holds a point (the grid, a whole shell cell by
// cell, or the thesis's scans), barycentric weights, the visible-overlap test.
#include <algorithm>
#include <cmath>

#include "plugins/tetra_brain/NativeTetBackend.h"

namespace trephine::tetra {

bool NativeTetBackend::inside(int32_t tet, const Vec3& p) const {
  if (m_holdsNoPoint[tet]) return false;
  const TetIndices& k = m_mesh->tets[tet];
  const Vec3 &a = m_nodes[k[0]], &b = m_nodes[k[1]], &c = m_nodes[k[2]], &d = m_nodes[k[3]];
  // Barycentric coordinates as sub-volumes; all of them non-negative inside (the
  // tets are positively oriented). A point on a face is inside both tets sharing it.
  const double tolerance = -1e-12 * signedVolume(a, b, c, d);
  return signedVolume(p, b, c, d) >= tolerance && signedVolume(a, p, c, d) >= tolerance &&
         signedVolume(a, b, p, d) >= tolerance && signedVolume(a, b, c, p) >= tolerance;
}

int32_t NativeTetBackend::locate(const Vec3& p) const {
  // A tet holding p now had its rest box within the displacement bound of p.
  const double slack = m_displacementBound;
  auto nearBox = [&](int32_t tet) {
    const Box3& box = m_grids->boxes[tet];
    if ((p.array() < box.min().array() - slack).any() || (p.array() > box.max().array() + slack).any()) return false;
    return slack == 0 || currentBox(tet).contains(p);  // tight once nodes moved (see locatePoints)
  };
  if (m_queryGrowth == 0) {
    const int64_t cell = m_grids->tetGrid.cellOf(p);
    if (cell < 0) return -1;
    for (int32_t tet : m_grids->tetGrid.items(cell))
      if (nearBox(tet) && inside(tet, p)) return tet;  // cells list tets in increasing order: the lowest index wins
    return -1;
  }
  // Nodes moved farther than the grid's margin: every cell within the excess.
  const Vec3 e = Vec3::Constant(m_queryGrowth);
  std::array<int32_t, 3> lo, hi;
  if (!m_grids->tetGrid.cellRange(Box3(p - e, p + e), lo, hi)) return -1;
  int32_t found = -1;
  m_tetVisits.begin();
  for (int32_t k = lo[2]; k <= hi[2]; ++k)
    for (int32_t j = lo[1]; j <= hi[1]; ++j)
      for (int32_t i = lo[0]; i <= hi[0]; ++i)
        for (int32_t tet : m_grids->tetGrid.items(m_grids->tetGrid.cellIndex(i, j, k))) {
          if (found >= 0 && tet >= found) break;
          if (m_tetVisits.firstVisit(tet) && nearBox(tet) && inside(tet, p)) found = tet;
        }
  return found;
}

bool NativeTetBackend::locatePoints(std::span<const Vec3> points, std::span<int32_t> tets, bool stopAtFirst) const {
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
  m_locator.group(m_grids->tetGrid, points);
  const Vec3 slack = Vec3::Constant(m_displacementBound);
  const bool moved = m_displacementBound > 0;
  // The work counts in locals (registers), added to the totals once a query:
  // the innermost loop stays a load and a compare.
  LocateWork work;
  work.queries = 1;
  m_locator.forEachCell([&](int64_t cell, const Box3& pointsBox, int32_t first) {
    if (any && stopAtFirst) return;
    const auto listed = m_grids->tetGrid.items(cell);
    ++work.cells;
    work.listed += listed.size();
    for (int32_t tet : listed) {  // increasing: the first tet found for a point is the lowest
      Vec3 lo = m_grids->boxes[tet].min() - slack, hi = m_grids->boxes[tet].max() + slack;
      if ((pointsBox.max().array() < lo.array()).any() || (pointsBox.min().array() > hi.array()).any()) continue;
      ++work.overlapping;
      if (moved) {
        // The grids' box grown by the drift may hold the points, the tet's
        // box now (four node reads) is tight: most points end here, not in
        // the four volumes of inside().
        const Box3 now = currentBox(tet);
        lo = now.min();
        hi = now.max();
        if ((pointsBox.max().array() < lo.array()).any() || (pointsBox.min().array() > hi.array()).any()) continue;
      }
      for (int32_t i = first; i >= 0; i = m_locator.nextPoint(i)) {
        if (tets[i] >= 0) continue;
        const Vec3& p = points[i];
        ++work.pointTests;
        if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
        ++work.insideTests;
        if (!inside(tet, p)) continue;
        tets[i] = tet;
        any = true;
        if (stopAtFirst) return;
      }
    }
  });
  m_locateWork.queries += work.queries;
  m_locateWork.cells += work.cells;
  m_locateWork.listed += work.listed;
  m_locateWork.overlapping += work.overlapping;
  m_locateWork.pointTests += work.pointTests;
  m_locateWork.insideTests += work.insideTests;
  return any;
}

std::array<double, 4> NativeTetBackend::barycentric(int32_t tet, const Vec3& p) const {
  const TetIndices& k = m_mesh->tets[tet];
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

std::span<TetHit> NativeTetBackend::findHits(const Pose& X_WT, std::span<const ShellPoint> shell,
                                             int32_t& searchStart) {
  if (shell.size() > m_hits.size()) return {};  // working memory is sized by reserveShell()
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  size_t hits = 0;
  if (m_options.search == Search::kGrid) {
    for (size_t i = 0; i < shell.size(); ++i) m_points[i] = R * shell[i].position + X_WT.position;
    const std::span<const Vec3> points(m_points.data(), shell.size());
    if (locatePoints(points, m_pointTets, false))
      for (size_t i = 0; i < shell.size(); ++i)
        if (m_pointTets[i] >= 0) m_hits[hits++] = {m_pointTets[i], int32_t(i)};
  } else {
    hits = findHitsByScan(R, X_WT.position, shell, searchStart);
  }
  return {m_hits.data(), hits};
}

size_t NativeTetBackend::findHitsByScan(const Eigen::Matrix3d& R, const Vec3& t, std::span<const ShellPoint> shell,
                                        int32_t& searchStart) {
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
  const int32_t n = int32_t(m_mesh->tetCount());
  const int32_t start =
      m_options.search == Search::kPreviousContact && searchStart >= 0 && searchStart < n ? searchStart : 0;
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
  searchStart = first;
  // Two rings of face neighbours, without repeats (a handful of tets: a linear check suffices).
  size_t count = 0;
  m_candidates[count++] = first;
  size_t ringStart = 0;
  for (int ring = 0; ring < 2; ++ring) {
    const size_t ringEnd = count;
    for (size_t c = ringStart; c < ringEnd; ++c)
      for (int f = 0; f < 4; ++f) {
        const int32_t nb = m_topology->neighbour(m_candidates[c], f);
        if (nb < 0 || m_holdsNoPoint[size_t(nb)] == kRemovedTet ||
            std::find(m_candidates.begin(), m_candidates.begin() + count, nb) != m_candidates.begin() + count)
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

bool NativeTetBackend::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  // Visible overlap: the tool's centre, or its shell pulled inwards by ten contact
  // depths, is inside the mesh.
  if (locate(X_WT.position) >= 0) return true;
  const Box3 grown(m_bounds.min() - Vec3::Constant(1.0), m_bounds.max() + Vec3::Constant(1.0));
  if (!grown.contains(X_WT.position)) {
    double radius = 0;
    for (const ShellPoint& p : shell) radius = std::max(radius, p.position.norm());
    if (grown.exteriorDistance(X_WT.position) > radius) return false;
  }
  const double inset = 10 * m_options.contactDepth;
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  if (shell.size() > m_insetPoints.size()) return false;  // not a reserved shell
  double reach = 0;  // mm, of the inset points from the centre
  for (size_t i = 0; i < shell.size(); ++i) {
    const double pull = std::min(inset, shell[i].position.norm());
    m_insetPoints[i] = R * (shell[i].position + pull * shell[i].inwardNormal) + X_WT.position;
    reach = std::max(reach, (m_insetPoints[i] - X_WT.position).squaredNorm());
  }
  // The centre is outside: if no boundary face comes within the inset
  // points' reach of it, the ball holding them is outside as a whole (the
  // usual case of a tool resting on the surface), and none is tested.
  if (!surfaceWithin(X_WT.position, std::sqrt(reach) + 1e-9)) return false;
  return locatePoints({m_insetPoints.data(), shell.size()}, m_insetTets, true);
}

}  // namespace trephine::tetra
