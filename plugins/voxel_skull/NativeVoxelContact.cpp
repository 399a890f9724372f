// The native back-end of VoxelSkull: detection and the contact parameters
// (thesis section 3.2 and Algorithm 1), and the overlap test of a displayed proxy.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "plugins/voxel_skull/NativeVoxelBackend.h"
#include "plugins/voxel_skull/VoxelTraversal.h"

namespace trephine::voxel {

namespace {

// Distance (mm) from p, inside solid voxel `voxel`, along unit n to the first
// free voxel. Most contact points are in the bone's outer voxel layer, so the
// exit of their own voxel is computed directly and the full traversal is only
// needed when the next voxel is solid too.
double depthToFreeVoxel(const SolidGrid& grid, const Vec3& p, int64_t voxel, const Vec3& n, double reach) {
  const Vec3 g = (p - grid.corner).cwiseProduct(grid.inverseSpacing);
  const Vec3 gd = n.cwiseProduct(grid.inverseSpacing);
  int64_t cell[3] = {voxel % grid.nx, (voxel / grid.nx) % grid.ny, voxel / (int64_t(grid.nx) * grid.ny)};
  double exit = std::numeric_limits<double>::infinity();
  int axis = 0;
  for (int a = 0; a < 3; ++a) {
    double t = std::numeric_limits<double>::infinity();
    if (gd[a] > 0) t = (double(cell[a] + 1) - g[a]) / gd[a];
    if (gd[a] < 0) t = (g[a] - double(cell[a])) / -gd[a];
    if (t < exit) exit = t, axis = a;
  }
  if (!std::isfinite(exit)) return 0;
  cell[axis] += gd[axis] > 0 ? 1 : -1;
  if (!grid.solidCell(cell[0], cell[1], cell[2])) return std::max(0.0, exit);
  return reach * firstFreeOnSegment(grid, p, p + reach * n);
}

// The direction a point in bone pushes the tool, for the contact normal. A
// sphere's inward normals meet at its centre, so their depth-weighted mean
// is the way out of a locally flat surface. Other tools' do not: the wall of
// a shaft pressed into bone at a tilt has normals square to the shaft, and
// their mean leans from the surface's normal by the tilt (a pointshell's
// known bias). For those, the density's gradient gives the surface's
// direction, unless it points back into the tool (deeper than the surface's
// first voxels, that is the bone's inner structure, not its surface).
Vec3 contactDirection(const SolidGrid& grid, const Vec3& p, const Vec3& toolNormal, bool sphere) {
  if (sphere) return toolNormal;
  Vec3 gradient;
  grid.codeAt(p, &gradient);
  const double slope = gradient.norm();
  if (!(slope * grid.smallestSide() > 1e-3 * std::max(1.0, std::abs(grid.isoCode)))) return toolNormal;
  const Vec3 outward = -gradient / slope;
  return outward.dot(toolNormal) > 0 ? outward : toolNormal;  // not pointing back into the tool
}

}  // namespace

// The thesis's detection: which shell points are in bone (the point test over
// the occupancy cells); the contact parameters are the narrow phase.
size_t NativeVoxelBackend::broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) {
  const ReservedShell* reserved = findShell(shell);
  if (!reserved) return 0;
  m_pointTest(grid(), reserved->arrays, X_WT, {m_voxels.data(), m_solid.data()});
  size_t inBone = 0;
  for (size_t i = 0; i < shell.size(); ++i) inBone += m_solid[i] != 0;
  return inBone;
}

VoxelContact NativeVoxelBackend::collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool touchedVoxels) {
  VoxelContact result;
  ShellContact& contact = result.contact;
  const ReservedShell* reserved = findShell(shell);
  if (!reserved) {  // a shell nobody announced: counted, not tested (no allocation here)
    ++m_unreservedShellCalls;
    return result;
  }
  const size_t n = shell.size();
  // Colliding box: the tool's bounds against the volume's.
  const Box3 toolBox(X_WT.position - Vec3::Constant(reserved->radius),
                     X_WT.position + Vec3::Constant(reserved->radius));
  if (!volume().bounds().intersects(toolBox)) return result;

  m_pointTest(grid(), reserved->arrays, X_WT, {m_voxels.data(), m_solid.data()});
  // The points in bone, 8 flags at a time: most of a touching shell is out of the bone.
  size_t hits = 0;
  size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    uint64_t flags;
    std::memcpy(&flags, m_solid.data() + i, 8);
    if (flags == 0) continue;
    for (size_t b = i; b < i + 8; ++b)
      if (m_solid[b]) m_hits[hits++] = {m_voxels[b], static_cast<int32_t>(b)};
  }
  for (; i < n; ++i)
    if (m_solid[i]) m_hits[hits++] = {m_voxels[i], static_cast<int32_t>(i)};
  if (hits == 0) return result;
  ++m_contactFrames;
  contact.points = static_cast<int>(hits);

  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  const bool algorithm1 = m_data.algorithm1;
  // Deepest-point depths are searched along the normal up to the tool's diameter.
  const double reach = 2.0 * reserved->radius + grid().spacing.maxCoeff();
  // Deepest-point variants weight each point's normal by its depth, so a point
  // entering or leaving the bone (depth near 0) does not turn the normal at once.
  Vec3 weightedSum = Vec3::Zero();
  // The points grouped by the voxel they are in: per voxel the sum of their
  // normals and (Algorithm 1) of -offset . normal, so that the sum of the
  // depths (centre - p) . normal is (centre - X) . sum(normal) - sum(offset . normal).
  m_groups.clear();
  for (size_t h = 0; h < hits; ++h) {
    bool isNew = false;
    const int32_t group = m_groups.groupOf(m_hits[h].voxel, isNew);
    if (isNew) m_groupNormals[group].setZero(), m_groupDepths[group] = 0, m_groupPoints[group] = 0;
    const ShellPoint& point = shell[m_hits[h].point];
    const Vec3 offset = R * point.position;  // mm, from the tool's reference point
    const Vec3 p = offset + X_WT.position;
    Vec3 normal = R * point.inwardNormal;  // out of the bone, towards the tool centre
    // Searched across the tool's width there and two voxels more (a voxel's
    // quantisation at either end): farther, the tool is in bone along the line.
    const double across = std::min(reach, reserved->width[m_hits[h].point] + 2 * grid().spacing.maxCoeff());
    if (algorithm1) {
      // McNeely tangent plane: through the voxel centre with the point's normal.
      m_groupDepths[group] -= offset.dot(normal);
    } else if (grid().smooth) {
      // Smooth surface: the surface normal and the first-order distance to
      // the isosurface, within half a voxel of it. Deeper, the first-order distance
      // is wrong where the density levels off inside bone (it overestimates),
      // and the gradient may be that of the bone's inner structure (a cortical
      // table over diploe rises outwards, turning the normal inwards): there,
      // as where the density is flat, the depth is measured along the tool's
      // normal instead.
      Vec3 gradient;
      const double code = grid().codeAt(p, &gradient);
      const double slope = gradient.norm();  // codes per mm
      const bool hasGradient = slope * grid().smallestSide() > 1e-3 * std::max(1.0, std::abs(grid().isoCode));
      const double firstOrderDepth = hasGradient ? (code - grid().isoCode) / slope : reach;
      if (hasGradient && firstOrderDepth <= 0.5 * grid().spacing.maxCoeff()) {
        normal = -gradient / slope;
        m_depths[h] = firstOrderDepth;
        m_buried[h] = 0;
      } else {
        const double t = firstFreeOnSegment(grid(), p, p + across * normal);
        m_depths[h] = across * t;
        m_buried[h] = t >= 1.0;
      }
      m_normals[h] = normal;
    } else {
      m_depths[h] = depthToFreeVoxel(grid(), p, m_hits[h].voxel, normal, across);
      m_buried[h] = m_depths[h] >= across;
      m_normals[h] = normal;
    }
    m_groupNormals[group] += normal;
    ++m_groupPoints[group];
    if (!algorithm1 && !m_buried[h]) weightedSum += m_depths[h] * contactDirection(grid(), p, normal, reserved->sphere);
  }
  Vec3 normalSum = Vec3::Zero();
  double penetration = 0;
  size_t touched = 0;  // the voxels the thesis's removal law cuts, when asked for
  const int voxels = static_cast<int>(m_groups.size());
  for (int32_t group = 0; group < voxels; ++group) {
    const int64_t voxel = m_groups.voxel(group);
    // Algorithm 1: the deepest of the per-voxel mean depths.
    if (algorithm1) {
      const double depthSum =
          (grid().centerOf(voxel) - X_WT.position).dot(m_groupNormals[group]) + m_groupDepths[group];
      penetration = std::max(penetration, depthSum / double(m_groupPoints[group]));
    }
    const double length = m_groupNormals[group].norm();
    if (length > 1e-12) normalSum += m_groupNormals[group] / length;  // Eq. 3.4: one unit normal per voxel
    if (touchedVoxels && !grid().smooth) m_touched[touched++] = voxel;
  }
  if (touchedVoxels && grid().smooth) {
    // Smooth surface: the density at a point comes from the 8 voxel centres
    // around it, so the burr cuts all of them (each once per frame).
    size_t count = 0;
    for (size_t h = 0; h < hits; ++h) {
      const Vec3 p = R * shell[m_hits[h].point].position + X_WT.position;
      const Vec3 u = (p - grid().corner).cwiseProduct(grid().inverseSpacing) - Vec3::Constant(0.5);
      const int64_t i = int64_t(std::floor(u.x())), j = int64_t(std::floor(u.y())), k = int64_t(std::floor(u.z()));
      for (int corner = 0; corner < 8; ++corner) {
        const int64_t a = i + (corner & 1), b = j + ((corner >> 1) & 1), c = k + (corner >> 2);
        if (grid().inside(a, b, c)) m_touched[count++] = grid().linear(a, b, c);
      }
    }
    std::sort(m_touched.begin(), m_touched.begin() + count);
    touched = size_t(std::unique(m_touched.begin(), m_touched.begin() + count) - m_touched.begin());
  }
  // The average vanishes when contacts surround the tool: no direction is given then.
  const double sumLength = normalSum.norm();
  contact.normal = sumLength > 1e-3 * voxels ? Vec3(normalSum / sumLength) : Vec3::Zero();
  const double weightedLength = weightedSum.norm();
  if (!algorithm1 && weightedLength > 1e-9) contact.normal = weightedSum / weightedLength;
  if (!algorithm1) {
    // The deepest point measured along the contact normal. A buried point's
    // own depth is not known (its normal never left the bone); the deepest of
    // them along the normal (the lowest below a flat surface) is measured
    // along the normal itself. Without a normal, every point is buried: the
    // tool is in bone across its width wherever it is touched.
    const bool directed = contact.normal.squaredNorm() > 0;
    double lowest = std::numeric_limits<double>::infinity();
    size_t deepestBuried = hits;
    for (size_t h = 0; h < hits; ++h) {
      if (!m_buried[h]) {
        penetration = std::max(penetration, m_depths[h] * std::max(0.0, m_normals[h].dot(contact.normal)));
        continue;
      }
      if (!directed) {
        penetration = std::max(penetration, m_depths[h]);
        continue;
      }
      const double height = (R * shell[m_hits[h].point].position).dot(contact.normal);
      if (height < lowest) lowest = height, deepestBuried = h;
    }
    if (directed && deepestBuried < hits) {
      const Vec3 p = R * shell[m_hits[deepestBuried].point].position + X_WT.position;
      penetration = std::max(penetration, reach * firstFreeOnSegment(grid(), p, p + reach * contact.normal));
    }
  }
  contact.primitives = voxels;
  contact.penetration = penetration;
  result.touched = {m_touched.data(), touched};
  m_maxCollidingVoxels = std::max<uint64_t>(m_maxCollidingVoxels, voxels);
  return result;
}

bool NativeVoxelBackend::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  // Visible overlap: the tool's centre, or its shell pulled one voxel inwards, is
  // in a bone voxel. Voxels suffice at a tolerance of one voxel (and cost a
  // quarter of the smooth test).
  const int64_t centre = grid().voxelOf(X_WT.position);
  if (centre >= 0 && grid().codes[centre] >= grid().threshold) return true;
  const ReservedShell* reserved = findShell(shell);
  if (!reserved) return false;
  const Box3 toolBox(X_WT.position - Vec3::Constant(reserved->radius),
                     X_WT.position + Vec3::Constant(reserved->radius));
  if (!volume().bounds().intersects(toolBox)) return false;
  m_voxelPointTest(grid(), reserved->inset, X_WT, {m_voxels.data(), m_solid.data()});
  for (size_t i = 0; i < reserved->inset.size(); ++i)
    if (m_solid[i]) return true;
  return false;
}

}  // namespace trephine::voxel
