// VoxelSkull: the sweeps that keep the proxy out of the bone (thesis section
// 3.2: before moving, and rectifying), and the ray cast that aims scripted paths.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "framework/geometry/FrontRings.h"
#include "plugins/voxel_skull/VoxelSkull.h"
#include "plugins/voxel_skull/VoxelTraversal.h"

namespace trephine::voxel {

SweepResult VoxelSkull::sweep(const SweepQuery& query) const {
  SweepResult result;
  const Vec3 path = query.to - query.from;
  const double length = path.norm();
  if (!(length > 0) || !std::isfinite(length)) return result;
  const Vec3 u = path / length;
  const double R = query.leadingRadius;

  // A proxy whose centre is in bone (it started there) may move anywhere out of it:
  // only material it newly enters blocks it.
  const bool buried = m_grid.solidAt(query.from);
  if (query.probe == SweepProbe::Spheres) {
    // A string of spheres: the whole shell at steps of the smallest voxel side.
    const ReservedShell* reserved = findShell(query.shell);
    if (!reserved) return result;
    const double step = m_grid.smallestSide();
    const int steps = static_cast<int>(std::ceil(length / step));
    const Eigen::Matrix3d Rm = query.orientation.toRotationMatrix();
    for (int k = 0; k <= steps; ++k) {
      const Vec3 offset = query.from + std::min(k * step, length) * u;
      for (size_t i = 0; i < query.shell.size(); ++i) {
        const ShellPoint& point = query.shell[i];
        const bool solid = m_grid.solidAt(Rm * point.position + offset);
        if (k == 0) {
          // Points already in bone do not block unless they face the motion (pressing further in).
          if (solid && !buried && -(Rm * point.inwardNormal).dot(u) > 0.5) {
            result.blocked = result.startsInside = true;
            result.freeFraction = 0;
            result.contactPoint = Rm * point.position + offset;
            return result;
          }
        } else if (solid && !m_wasSolid[i]) {
          result.blocked = true;
          result.freeFraction = std::max(0.0, (k - 1) * step / length);
          result.contactPoint = Rm * point.position + offset;
          return result;
        }
        m_wasSolid[i] = solid;
      }
    }
    return result;
  }

  // Line: the leading point of the tool, exactly voxel by voxel. If it starts in
  // bone the tool already presses that way: it stays.
  const Vec3 lead = R * u;
  double first = 2.0;
  const SegmentHit hit = firstSolidOnSegment(m_grid, query.from + lead, query.to + lead, buried);
  Vec3 firstProbe = lead;  // where, relative to the tool's reference point, the blocking probe starts
  if (hit.hit) {
    if (hit.startsSolid && !buried) {
      result.blocked = result.startsInside = true;
      result.freeFraction = 0;
      result.contactPoint = query.from + lead;
      return result;
    }
    first = hit.t;
  }
  if (query.probe == SweepProbe::Cylinder && R > 0) {
    // Cylinder: the swept front of the tool, as lines from rings on its front
    // hemisphere (radius R on the equator, 0.87 R and 0.5 R further ahead),
    // dense enough that no voxel passes between two lines. Lines from the front
    // rings block like the leading point; lines from the equator may start in
    // the bone the tool slides on and block only on entering new bone.
    // Each line is traversed only as far as the nearest block found so far: a
    // hit beyond it could not move the stop (same result, and a tool pressed
    // deep into bone no longer traverses the whole path from every ring point).
    const bool stopped = forEachFrontRingPoint(u, R, m_grid.smallestSide(), [&](const Vec3& offset, bool front) {
      const double reach = first > 0 ? std::min(first, 1.0) : 1.0;
      SegmentHit ring = firstSolidOnSegment(m_grid, query.from + offset, query.from + offset + reach * path,
                                            buried || !front);
      if (!ring.hit) return false;
      ring.t *= reach;
      if (front && ring.startsSolid && !buried) {
        result.blocked = result.startsInside = true;
        result.freeFraction = 0;
        result.contactPoint = query.from + offset;
        return true;
      }
      if (ring.t < first) {
        first = ring.t;
        firstProbe = offset;
      }
      return false;
    });
    if (stopped) return result;
  }
  if (first <= 1.0) {
    result.blocked = true;
    result.freeFraction = first;
    result.contactPoint = query.from + firstProbe + first * path;
  }
  return result;
}

Vec3 VoxelSkull::densityGradient(const Vec3& p) const {
  // Central differences of the solid indicator's density over one voxel (per mm).
  Vec3 g;
  for (int a = 0; a < 3; ++a) {
    const Vec3 d = Vec3::Unit(a) * m_grid.spacing[a];
    auto densityAt = [&](const Vec3& q) {
      const int64_t v = m_grid.voxelOf(q);
      return v < 0 ? 0.0 : m_volume.encoding().density(m_grid.codes[v]);
    };
    g[a] = (densityAt(p + d) - densityAt(p - d)) / (2 * m_grid.spacing[a]);
  }
  return g;
}

std::optional<SurfaceHit> VoxelSkull::raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const {
  const SegmentHit hit = firstSolidOnSegment(m_grid, origin, origin + maxDistance * direction, false);
  if (!hit.hit) return std::nullopt;
  SurfaceHit out;
  out.distance = hit.t * maxDistance;
  out.point = origin + out.distance * direction;
  // The outward normal: against the density gradient around the hit, or the entered face.
  const Vec3 gradient = densityGradient(out.point);
  if (gradient.norm() > 1e-12 && gradient.normalized().dot(direction) > 0) {
    out.normal = -gradient.normalized();
  } else if (hit.enteredAxis >= 0) {
    out.normal = Vec3::Zero();
    out.normal[hit.enteredAxis] = direction[hit.enteredAxis] > 0 ? -1.0 : 1.0;
  } else {
    out.normal = -direction;
  }
  return out;
}

}  // namespace trephine::voxel
