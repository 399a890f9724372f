#include "tools/trephine/study/ExactSphereContact.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace trephine::study {

namespace {

constexpr int kDirections = 600;     // first pass: about 8 deg between neighbours
constexpr int kRingDirections = 12;  // per refinement ring
constexpr int kRefinements = 24;     // ring radius shrinks by kRingShrink each time: 1e-5 rad at the end
constexpr int kMaxMoves = 400;       // ring moves without shrinking
constexpr double kRingShrink = 0.6;
constexpr int kBisections = 40;  // the step over 2^40: far below a nanometre

// First point along center + t u (0 < t <= reach) where the solid's sign
// differs from the centre's; infinity if none.
double firstCrossing(const LevelSet& solid, const Vec3& center, const Vec3& u, bool startInside, double reach,
                     double step) {
  double previous = 0;
  for (double t = step;; t += step) {
    const double s = std::min(t, reach);
    const bool inside = solid(center + s * u) < 0;
    if (inside != startInside) {
      double lo = previous, hi = s;
      for (int i = 0; i < kBisections; ++i) {
        const double mid = 0.5 * (lo + hi);
        ((solid(center + mid * u) < 0) != startInside ? hi : lo) = mid;
      }
      return hi;
    }
    if (s >= reach) return std::numeric_limits<double>::infinity();
    previous = s;
  }
}

Vec3 fibonacciDirection(int i, int n) {
  const double z = 1.0 - (2.0 * i + 1.0) / n;
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = i * std::numbers::pi * (3.0 - std::sqrt(5.0));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

Vec3 gradient(const LevelSet& solid, const Vec3& p, double h) {
  Vec3 g;
  for (int a = 0; a < 3; ++a) {
    const Vec3 e = h * Vec3::Unit(a);
    g[a] = solid(p + e) - solid(p - e);
  }
  return g;
}

}  // namespace

ExactSphereContact exactSphereContact(const LevelSet& solid, const Vec3& center, double radius, double step) {
  const bool inside = solid(center) < 0;
  // Outside, a surface farther than the radius does not touch; inside, the
  // depth is searched further so that deep poses are still measured.
  const double reach = inside ? 4.0 * radius + 5.0 : radius + 1.0;
  double best = std::numeric_limits<double>::infinity();
  Vec3 bestDirection = Vec3::UnitZ();
  for (int i = 0; i < kDirections; ++i) {
    const Vec3 u = fibonacciDirection(i, kDirections);
    const double t = firstCrossing(solid, center, u, inside, std::min(reach, best), step);
    if (t < best) best = t, bestDirection = u;
  }
  ExactSphereContact contact;
  if (!std::isfinite(best)) {
    contact.penetration = inside ? radius + reach : radius - reach;
    return contact;
  }
  // Pattern search: a ring of directions around the best one; the ring
  // moves with every improvement and shrinks when none is found. At a crease
  // the distance falls only in a narrow wedge of directions, so a ring that
  // finds it is tried again before shrinking.
  double ring = std::sqrt(4.0 * std::numbers::pi / kDirections);  // rad, spacing of the first pass
  for (int shrinks = 0, moves = 0; shrinks < kRefinements && moves < kMaxMoves;) {
    const Vec3 a = bestDirection.unitOrthogonal(), b = bestDirection.cross(a);
    const Vec3 centreDirection = bestDirection;
    bool improved = false;
    for (int j = 0; j < kRingDirections; ++j) {
      const double theta = 2.0 * std::numbers::pi * j / kRingDirections;
      const Vec3 u = (std::cos(ring) * centreDirection + std::sin(ring) * (std::cos(theta) * a + std::sin(theta) * b))
                         .normalized();
      const double t = firstCrossing(solid, center, u, inside, best, step);
      if (t < best) best = t, bestDirection = u, improved = true;
    }
    if (improved) {
      ++moves;
    } else {
      ring *= kRingShrink;
      ++shrinks;
    }
  }
  contact.penetration = inside ? radius + best : radius - best;
  if (contact.penetration <= 0) return contact;
  if (best > 1e-6) {
    // Outside, the normal points from the surface point back to the centre;
    // inside, from the centre out through the nearest surface point.
    contact.normal = inside ? bestDirection : Vec3(-bestDirection);
  } else {
    const Vec3 g = gradient(solid, center, 1e-4);
    if (g.norm() > 0) contact.normal = g.normalized();
  }
  return contact;
}

}  // namespace trephine::study
