#pragma once
// The exact contact of a sphere with a solid given by a level set: the
// reference a study measures every back-end against. Offline only (a few ms
// per query).
#include "framework/geometry/ExactShape.h"

namespace trephine::study {

struct ExactSphereContact {
  // mm: radius minus the distance from the centre to the solid when the
  // centre is outside, radius plus the centre's depth below the surface when
  // inside. <= 0: the sphere does not reach the solid.
  double penetration = 0;
  Vec3 normal = Vec3::Zero();  // unit, out of the solid towards the centre; zero without contact
};

// Finds the surface point closest to `center` by searching over directions:
// rays in a Fibonacci set of directions are marched at `step` (mm) to the
// first change of sign and bisected, then the best direction is refined on
// shrinking rings around it (a pattern search). A centre outside is searched
// up to `radius` + 1 mm (farther the sphere cannot touch); a centre inside up
// to 4 `radius` + 5 mm, and deeper still the penetration returned is that
// reach, a lower bound. Features thinner than `step` can be missed.
ExactSphereContact exactSphereContact(const LevelSet& solid, const Vec3& center, double radius, double step = 0.05);

}  // namespace trephine::study
