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

// Calls visit(offset, front) for each ring point: `offset` from the sphere's
// centre (mm), `front` false on the equator (lines that may start in what the
// sphere slides on). Stops when visit returns true; returns whether it did.
template <typename Visit>
bool forEachFrontRingPoint(const Vec3& u, double radius, double spacing, Visit&& visit) {
  const auto [e1, e2] = perpendicularBasis(u);
  for (const double ahead : {0.866, 0.5, 0.0}) {
    const double r = radius * std::sqrt(1.0 - ahead * ahead);
    const int count = std::max(6, static_cast<int>(std::ceil(2 * std::numbers::pi * r / spacing)));
    for (int i = 0; i < count; ++i) {
      const double phi = 2 * std::numbers::pi * i / count;
      if (visit(Vec3(r * (std::cos(phi) * e1 + std::sin(phi) * e2) + ahead * radius * u), ahead > 0)) return true;
    }
  }
  return false;
}

}  // namespace trephine
