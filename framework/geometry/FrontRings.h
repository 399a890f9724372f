#pragma once
// The lines a sweep probes the front of a moving sphere with (the cylinder
// sweep of the rigid and the tetrahedral targets): besides the leading point,
// rings about the direction of motion u on the sphere's front hemisphere, at
// 0.87 R and 0.5 R ahead of the centre and on its equator, with points at most
// `spacing` apart around each ring (at least 6) so that nothing of that size
// passes between two lines.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "framework/math/Math.h"

namespace trephine {

// Two unit vectors spanning the plane orthogonal to unit `n`.
inline std::pair<Vec3, Vec3> perpendicularBasis(const Vec3& n) {
  const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = n.cross(helper).normalized();
  return {e1, n.cross(e1)};
}

// The rings' distances ahead of the centre, as fractions of the radius.
inline constexpr double kFrontRingsAhead[3] = {0.866, 0.5, 0.0};

inline int frontRingCount(double ringRadius, double spacing) {
  return std::max(6, static_cast<int>(std::ceil(2 * std::numbers::pi * ringRadius / spacing)));
}

// How many points forEachFrontRingPoint visits for this radius and spacing
// (for sizing working memory ahead of the haptic loop).
inline int frontRingPointCount(double radius, double spacing) {
  int count = 0;
  for (const double ahead : kFrontRingsAhead) count += frontRingCount(radius * std::sqrt(1.0 - ahead * ahead), spacing);
  return count;
}

// Calls visit(offset, front) for each ring point: `offset` from the sphere's
// centre (mm), `front` false on the equator (lines that may start in what the
// sphere slides on). Stops when visit returns true; returns whether it did.
template <typename Visit>
bool forEachFrontRingPoint(const Vec3& u, double radius, double spacing, Visit&& visit) {
  const auto [e1, e2] = perpendicularBasis(u);
  for (const double ahead : kFrontRingsAhead) {
    const double r = radius * std::sqrt(1.0 - ahead * ahead);
    const int count = frontRingCount(r, spacing);
    // Around the ring by rotating (cos, sin) one step at a time: one sine and
    // cosine per ring instead of per point (the sweeps run twice a haptic
    // frame; 76 points for a 2.5 mm burr on 0.5 mm voxels). The rounding
    // drifts by about 1e-16 a step.
    const double stepCos = std::cos(2 * std::numbers::pi / count), stepSin = std::sin(2 * std::numbers::pi / count);
    double c = 1, s = 0;
    const Vec3 centre = ahead * radius * u;
    for (int i = 0; i < count; ++i) {
      if (visit(Vec3(centre + r * (c * e1 + s * e2)), ahead > 0)) return true;
      const double next = c * stepCos - s * stepSin;
      s = s * stepCos + c * stepSin;
      c = next;
    }
  }
  return false;
}

}  // namespace trephine
