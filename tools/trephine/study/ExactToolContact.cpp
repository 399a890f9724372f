#include "tools/trephine/study/ExactToolContact.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace trephine::study {

namespace {

// The depth the shaft's cross-section at axis point p reaches (mm, <= 0 when
// it does not reach the solid), and the direction of the nearest surface
// point's normal there.
struct DiscDepth {
  double depth = -std::numeric_limits<double>::infinity();
  Vec3 normal = Vec3::Zero();
};

DiscDepth discDepth(const SphereReference& sphere, const Vec3& p, const Vec3& axis, double rho) {
  // A sphere of the shaft's radius holds the disc: if it does not reach, neither does the disc.
  const ExactSphereContact c = sphere(p, rho);
  DiscDepth d;
  if (!(c.penetration > 0) || !c.normal.allFinite() || c.normal.squaredNorm() == 0) return d;
  const double across = c.normal.cross(axis).norm();  // |n x a|: the normal's part square to the axis
  d.depth = (c.penetration - rho) + rho * across;     // -sd(p) + rho |n x a|
  d.normal = c.normal;
  return d;
}

}  // namespace

ExactSphereContact exactToolContact(const SphereReference& sphere, const Pose& X_WT, const ToolSolid& tool,
                                    double axisStep) {
  const Vec3& centre = X_WT.position;
  ExactSphereContact best = sphere(centre, tool.radius);
  const double rho = tool.shaftRadius, length = tool.shaftLength;
  if (!(length > 0) || !(rho > 0)) return best;
  const Vec3 axis = (X_WT.orientation * tool.shaftAxis).normalized();
  const auto at = [&](double s) { return Vec3(centre + s * axis); };
  // Coarse: spheres centred every `span` along the axis, of the radius that
  // covers the cylinder between their neighbours; a stretch whose sphere
  // does not reach the solid is skipped.
  const double span = std::max(2.0 * axisStep, rho);
  const double cover = std::sqrt(rho * rho + 0.25 * span * span);
  double bestS = -1;
  DiscDepth bestDisc;
  for (double s0 = 0; s0 < length + 0.5 * span; s0 += span) {
    const double mid = std::min(s0 + 0.5 * span, length);
    if (!(sphere(at(mid), cover).penetration > 0)) continue;
    for (double s = s0; s <= std::min(s0 + span, length) + 1e-12; s += axisStep) {
      const DiscDepth d = discDepth(sphere, at(std::min(s, length)), axis, rho);
      if (d.depth > bestDisc.depth) bestDisc = d, bestS = std::min(s, length);
    }
  }
  if (bestS < 0 || !(bestDisc.depth > 0)) return best;
  // Golden-section search on the axis around the best sample.
  double lo = std::max(0.0, bestS - axisStep), hi = std::min(length, bestS + axisStep);
  constexpr double kGolden = 0.6180339887498949;
  for (int i = 0; i < 30 && hi - lo > 1e-6; ++i) {
    const double a = hi - kGolden * (hi - lo), b = lo + kGolden * (hi - lo);
    const DiscDepth da = discDepth(sphere, at(a), axis, rho), db = discDepth(sphere, at(b), axis, rho);
    if (da.depth > bestDisc.depth) bestDisc = da;
    if (db.depth > bestDisc.depth) bestDisc = db;
    (da.depth >= db.depth ? hi : lo) = da.depth >= db.depth ? b : a;
  }
  if (bestDisc.depth > best.penetration) {
    best.penetration = bestDisc.depth;
    best.normal = bestDisc.normal;
  }
  return best;
}

}  // namespace trephine::study
