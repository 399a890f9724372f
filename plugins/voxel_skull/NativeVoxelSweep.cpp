// The native back-end of VoxelSkull: the sweeps that keep the proxy out of the bone (thesis section
// 3.2: before moving, and rectifying), and the ray cast that aims scripted paths.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "framework/geometry/FrontRings.h"
#include "plugins/voxel_skull/NativeVoxelBackend.h"
#include "plugins/voxel_skull/VoxelTraversal.h"

namespace trephine::voxel {

double NativeVoxelBackend::resolvedFeature(double R) const {
  return std::max(grid().smallestSide(), R / kToolResolution);
}

bool NativeVoxelBackend::clipPathToGrid(const Vec3& from, const Vec3& to, double reach, double& t0,
                                        double& t1) const {
  t0 = 0, t1 = 1;
  // Outside a volume is its lowest density: never bone unless the isovalue
  // lies below it, when everything is bone and nothing can be clipped.
  if (grid().smooth ? grid().outsideCode > grid().isoCode : grid().threshold <= grid().outsideCode) return true;
  const Vec3 pad = Vec3::Constant(reach) + 2.0 * grid().spacing;  // the interpolation reaches 1.5 voxels out
  const Vec3 lo = grid().corner - pad;
  const Vec3 hi = grid().corner + Vec3(grid().nx, grid().ny, grid().nz).cwiseProduct(grid().spacing) + pad;
  const Vec3 d = to - from;
  for (int axis = 0; axis < 3; ++axis) {
    if (d[axis] == 0) {
      if (from[axis] < lo[axis] || from[axis] > hi[axis]) return false;
      continue;
    }
    double ta = (lo[axis] - from[axis]) / d[axis], tb = (hi[axis] - from[axis]) / d[axis];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}

SweepResult NativeVoxelBackend::sweep(const SweepQuery& query) const {
  SweepResult result;
  const Vec3 path = query.to - query.from;
  const double length = path.norm();
  if (!(length > 0) || !std::isfinite(length)) return result;
  const Vec3 u = path / length;
  const double R = query.leadingRadius;

  // A proxy whose centre is in bone (it started there) may move anywhere out of it:
  // only material it newly enters blocks it.
  const bool buried = grid().solidAt(query.from);
  if (query.probe == SweepProbe::Spheres) {
    // A string of spheres: the whole shell at steps of the smallest voxel side.
    const ReservedShell* reserved = findShell(query.shell);
    if (!reserved) return result;
    // Only the part of the path where the shell can meet the grid is stepped.
    double t0 = 0, t1 = 1;
    if (!clipPathToGrid(query.from, query.to, reserved->radius, t0, t1)) return result;
    const double first = t0 * length, last = t1 * length;
    const double step = resolvedFeature(reserved->radius);
    const int steps = static_cast<int>(std::ceil((last - first) / step));
    m_mostSweepSteps = std::max<uint64_t>(m_mostSweepSteps, uint64_t(steps) + 1);
    const Eigen::Matrix3d Rm = query.orientation.toRotationMatrix();
    for (int k = 0; k <= steps; ++k) {
      const Vec3 offset = query.from + std::min(first + k * step, last) * u;
      // The whole shell at once (the vectorised point test of the detection,
      // the same flags as solidAt point by point).
      m_pointTest(grid(), reserved->arrays, Pose{offset, query.orientation}, {m_voxels.data(), m_solid.data()});
      for (size_t i = 0; i < query.shell.size(); ++i) {
        const ShellPoint& point = query.shell[i];
        const bool solid = m_solid[i] != 0;
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
          result.freeFraction = std::max(0.0, (first + (k - 1) * step) / length);
          result.contactPoint = Rm * point.position + offset;
          return result;
        }
        m_wasSolid[i] = solid;
      }
    }
    return result;
  }

  if (grid().smooth && R >= 0 && (query.probe == SweepProbe::Line || query.probe == SweepProbe::Cylinder)) {
    const int lines = 1 + (query.probe == SweepProbe::Cylinder && R > 0
                               ? frontRingPointCount(R, resolvedFeature(R))
                               : 0);
    if (lines <= int(m_probeLines.size())) return sweepSmoothLines(query, buried);
  }

  // Line: the leading point of the tool, exactly voxel by voxel. If it starts in
  // bone the tool already presses that way: it stays.
  const Vec3 lead = R * u;
  double first = 2.0;
  const SegmentHit hit = firstSolidOnSegment(grid(), query.from + lead, query.to + lead, buried);
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
    const bool stopped = forEachFrontRingPoint(u, R, resolvedFeature(R), [&](const Vec3& offset, bool front) {
      const double reach = first > 0 ? std::min(first, 1.0) : 1.0;
      SegmentHit ring = firstSolidOnSegment(grid(), query.from + offset, query.from + offset + reach * path,
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

SweepResult NativeVoxelBackend::sweepSmoothLines(const SweepQuery& query, bool buried) const {
  // The smooth surface, probed by lines: the leading point's and, for the
  // cylinder, the rings'. All lines advance together, half a voxel a step,
  // and the sweep ends at the first step where any line enters new bone: a
  // crossing at a later step could not be nearer. Each step's points go
  // through the vectorised point test at once; only the lines that entered
  // bone at that step are refined, each only if it is in bone at the nearest
  // crossing found so far. Per line the rules of the voxel sweep hold: a front
  // line (the leading point, the rings ahead) that starts in bone blocks at
  // once unless the centre is buried; lines from the equator, and every line
  // of a buried tool, pass the bone they start in and block on entering new
  // bone.
  SweepResult result;
  const Vec3 path = query.to - query.from;
  const double length = path.norm();
  const Vec3 u = path / length;
  const double R = query.leadingRadius;
  int lines = 0;
  m_probeLines[lines++] = {R * u, true, false};
  if (query.probe == SweepProbe::Cylinder && R > 0)
    forEachFrontRingPoint(u, R, resolvedFeature(R), [&](const Vec3& offset, bool front) {
      m_probeLines[lines++] = {offset, front, false};
      return false;
    });
  ShellArrays& points = m_probePoints;
  points.x.resize(size_t(lines));  // within the capacity reserved ahead: no allocation
  points.y.resize(size_t(lines));
  points.z.resize(size_t(lines));
  const Pose identity{Vec3::Zero(), Quat::Identity()};
  // Only the part of the path where a line can meet the grid is stepped.
  double t0 = 0, t1 = 1;
  if (!clipPathToGrid(query.from, query.to, R, t0, t1)) return result;
  const int steps =
      std::max(1, static_cast<int>(std::ceil((t1 - t0) * length / (0.5 * resolvedFeature(R)))));
  m_mostSweepSteps = std::max<uint64_t>(m_mostSweepSteps, uint64_t(steps) + 1);
  const auto fractionAt = [&](int k) { return t0 + (t1 - t0) * double(k) / steps; };
  for (int k = 0; k <= steps; ++k) {
    const double t = fractionAt(k);
    for (int j = 0; j < lines; ++j) {
      const Vec3 p = query.from + m_probeLines[j].offset + t * path;
      points.x[size_t(j)] = p.x(), points.y[size_t(j)] = p.y(), points.z[size_t(j)] = p.z();
    }
    m_pointTest(grid(), points, identity, {m_probeVoxels.data(), m_probeSolid.data()});
    if (k == 0) {
      for (int j = 0; j < lines; ++j) {
        ProbeLine& line = m_probeLines[j];
        const bool solid = m_probeSolid[size_t(j)] != 0;
        if (solid && line.front && !buried) {
          result.blocked = result.startsInside = true;
          result.freeFraction = 0;
          result.contactPoint = query.from + line.offset;
          return result;
        }
        line.skipping = solid;
      }
      continue;
    }
    // Lines that enter bone at this step: the nearest crossing blocks.
    const double previous = fractionAt(k - 1);
    double nearest = 2.0;
    int nearestLine = -1;
    for (int j = 0; j < lines; ++j) {
      ProbeLine& line = m_probeLines[j];
      if (!m_probeSolid[size_t(j)]) {
        line.skipping = false;
        continue;
      }
      if (line.skipping) continue;
      const Vec3 a = query.from + line.offset, b = a + path;
      double upTo = t;
      if (nearestLine >= 0) {
        // Nearer than the crossing found only if already in bone there.
        if (!grid().solidAt(a + nearest * path)) continue;
        upTo = nearest;
      }
      nearest = crossingOnSegment(grid(), a, b, previous, upTo);
      nearestLine = j;
    }
    if (nearestLine >= 0) {
      result.blocked = true;
      result.freeFraction = nearest;
      result.contactPoint = query.from + m_probeLines[nearestLine].offset + nearest * path;
      return result;
    }
  }
  return result;
}

Vec3 NativeVoxelBackend::densityGradient(const Vec3& p) const {
  // Central differences of the solid indicator's density over one voxel (per mm).
  Vec3 g;
  for (int a = 0; a < 3; ++a) {
    const Vec3 d = Vec3::Unit(a) * grid().spacing[a];
    auto densityAt = [&](const Vec3& q) {
      const int64_t v = grid().voxelOf(q);
      return v < 0 ? 0.0 : volume().encoding().density(grid().codes[v]);
    };
    g[a] = (densityAt(p + d) - densityAt(p - d)) / (2 * grid().spacing[a]);
  }
  return g;
}

std::optional<SurfaceHit> NativeVoxelBackend::raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const {
  const SegmentHit hit = firstSolidOnSegment(grid(), origin, origin + maxDistance * direction, false);
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
