#pragma once
// The rules the mesh back-ends (embree, bullet) share for a spherical burr
// against the skull's isosurface, whichever library finds the triangles.
#include <algorithm>
#include <span>

#include "framework/geometry/ShellContactTarget.h"

namespace trephine::voxel {

// The sphere's contact from the closest surface point to its centre.
//   closest, distance: the closest point and its distance d from the centre
//   inside:            the centre is in the bone
//   weightedNormal:    the face normals of the triangles within reach, each
//                      times depth and area (summed; zero if none)
// Penetration r - d outside, r + d inside. The normal outside is the mean of
// the face normals (the closest point's own direction jumps from face to
// face at a crease, and a proxy lifted along it chatters), inside the way out
// through the closest point. `points` counts the shell points beyond the
// tangent plane at the closest point (at least 1). A centre on the surface
// (d = 0) has no direction: no contact.
inline ShellContact sphereContact(const Pose& X_WT, std::span<const ShellPoint> shell, double radius,
                                  const Vec3& closest, double distance, bool inside, const Vec3& weightedNormal) {
  ShellContact contact;
  if (!(distance > 0)) return contact;
  const Vec3& centre = X_WT.position;
  contact.normal = inside                                  ? Vec3((closest - centre) / distance)
                   : weightedNormal.norm() > 1e-9 * radius ? Vec3(weightedNormal.normalized())
                                                           : Vec3((centre - closest) / distance);
  contact.penetration = inside ? radius + distance : radius - distance;
  if (!(contact.penetration > 0)) return ShellContact{};
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  for (const ShellPoint& p : shell)
    contact.points += (R * p.position).dot(-contact.normal) > radius - contact.penetration;
  contact.points = std::max(contact.points, 1);
  return contact;
}

// How deep (mm) a swept sphere may go before it is stopped. A free sphere
// stops where it touches the surface (the proxy then adds its skin, the
// target's contact depth, a tenth of a voxel). One that touches at the start
// may sink one skin deeper than it starts, or than one skin: a proxy resting
// in its skin slides along the surface (a slide along the tangent plane sinks
// a little wherever the triangles fold inwards; the next frame's lift takes
// it back out), and a move into the surface stops at once (startsInside).
inline double sweepAllowance(bool touching, double startDepth, double skin) {
  return touching ? std::max(skin, startDepth) + skin : 0.0;
}

// The proxy's skin on the mesh back-ends: a tenth of the smallest voxel side (mm).
inline double meshSkin(double smallestVoxelSide) { return 0.1 * smallestVoxelSide; }

}  // namespace trephine::voxel
