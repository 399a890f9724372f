#pragma once
// The rules the mesh back-ends (embree, bullet) share for a spherical burr
// against a closed triangle surface (the skull's isosurface, the brain's
// boundary), whichever library finds the triangles.
#include <algorithm>
#include <span>
#include <vector>

#include "framework/geometry/ShellContactTarget.h"

namespace trephine {

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
// target's contact depth). One that touches at the start may sink one skin
// deeper than it starts, or than one skin: a proxy resting in its skin
// slides along the surface (a slide along the tangent plane sinks a little
// wherever the triangles fold inwards; the next frame's lift takes it back
// out), and a move into the surface stops at once (startsInside).
inline double sweepAllowance(bool touching, double startDepth, double skin) {
  return touching ? std::max(skin, startDepth) + skin : 0.0;
}

// The shells a mesh back-end was told of (reserveShell), with the sphere
// each is treated as.
struct ReservedShell {
  const ShellPoint* source = nullptr;
  size_t size = 0;
  double radius = 0;    // mm, the farthest point from the reference point
  bool sphere = false;  // every point at `radius` (to 1e-9)
};

class ReservedShells {
 public:
  const ReservedShell& add(std::span<const ShellPoint> shell) {
    if (const ReservedShell* known = find(shell)) return *known;
    ReservedShell reserved{shell.data(), shell.size(), 0, true};
    for (const ShellPoint& p : shell) reserved.radius = std::max(reserved.radius, p.position.norm());
    for (const ShellPoint& p : shell)
      reserved.sphere = reserved.sphere && p.position.norm() > (1 - 1e-9) * reserved.radius;
    m_shells.push_back(reserved);
    return m_shells.back();
  }
  const ReservedShell* find(std::span<const ShellPoint> shell) const {
    for (const ReservedShell& s : m_shells)
      if (s.source == shell.data() && s.size == shell.size()) return &s;
    return nullptr;
  }
  size_t largest() const {
    size_t n = 0;
    for (const ReservedShell& s : m_shells) n = std::max(n, s.size);
    return n;
  }

 private:
  std::vector<ReservedShell> m_shells;
};

}  // namespace trephine
