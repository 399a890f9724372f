#pragma once
// A proxy that moves its spring's anchor passively.
//
// The rendered spring runs from the device D to an anchor A (the proxy lifted
// out by its contact skin) and stores V = k |A - D|^2 / 2 (N mm = mJ). With the
// force F_k = k (A_k - D_k) held over frame k, the energy it gives the hand
// while the device moves by dx = D_{k+1} - D_k splits exactly into
//
//   F_k . dx = [V(A_k - D_k) - V(A_k - D_{k+1})]     the spring, anchor held
//            + k |dx|^2 / 2                           the hold (Colgate and
//                                                     Schenkelberg's K T / 2)
//            + [V(A_k - D_{k+1}) - V(A_{k+1} - D_{k+1})]  the anchor's move.
//
// A device damping b dissipates at least b |dx|^2 / T over the frame (Cauchy-
// Schwarz), which pays for the hold when b > k T / 2: the load-time check.
// Nothing pays for the last term when it is negative, i.e. when the anchor
// moves away from where the device now is. A god-object proxy at the free
// point nearest the device never does so on its own: last frame's anchor is
// still free (drilling only frees space), so the nearest free point is at most
// as far. A proxy that re-projects on a drilled, rough surface can: a lift out
// of a pit as shell points enter the bone, a turning normal swinging the skin,
// a footprint cut that changes which points collide. Holding every move of
// the anchor to |A_{k+1} - D_{k+1}| <= |A_k - D_{k+1}| makes the last term
// never negative, so with b > k T / 2 the energy the hand has put in, counted
// with the device's damping, never falls below what the spring holds (>= 0).
#include <algorithm>
#include <cmath>

#include "framework/math/Math.h"

namespace trephine::haptics {

// The anchor (mm) the proxy may take this frame: `wanted` when it is no
// farther from `device` than `last` (the anchor of the last frame); else the
// point of the segment from `last` towards `wanted` that goes farthest along
// it at that distance (the anchor follows the new contact as far as it can
// without stretching the spring beyond what the device's own move did).
inline Vec3 passiveAnchor(const Vec3& last, const Vec3& wanted, const Vec3& device) {
  const Vec3 held = last - device;  // mm, the spring with the anchor held
  const double bound = held.squaredNorm();
  if (!((wanted - device).squaredNorm() > bound)) return wanted;
  // |held + l u|^2 = |held|^2 at l = 0 and at l = -2 held.u / |u|^2, and is
  // smaller in between.
  const Vec3 u = wanted - last;
  const double uu = u.squaredNorm();
  const double l = uu > 0 ? std::clamp(-2.0 * held.dot(u) / uu, 0.0, 1.0) : 0.0;
  if (!(l > 0)) return last;  // every step towards `wanted` stretches the spring
  const Vec3 spring = held + l * u;
  // At the root itself rounding may leave it a hair longer: scale it back.
  const double length = spring.squaredNorm();
  return length > bound ? Vec3(device + std::sqrt(bound / length) * spring) : Vec3(device + spring);
}

}  // namespace trephine::haptics
