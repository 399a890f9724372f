#include "plugins/haptics/CapsuleShape.h"

#include <cmath>
#include <numbers>

#include "framework/core/Lifecycle.h"
#include "framework/geometry/ShellSampling.h"

namespace trephine::haptics {

CapsuleFields::CapsuleFields(FieldOwner* owner, const CapsuleDefaults& d)
    : radius{owner,
             "radius",
             d.radius,
             {.help = "Radius of the ball end (the burr; the aspirator's or the forceps' tip)", .unit = "mm", .min = 0.0, .minExclusive = true}},
      shaftRadius{owner,
                  "shaftRadius",
                  d.shaftRadius,
                  {.help = "Shaft radius (at most the ball end's)",
                   .unit = "mm",
                   .min = 0.0,
                   .minExclusive = true}},
      shaftLength{owner,
                  "shaftLength",
                  d.shaftLength,
                  {.help = "Shaft length from the ball end's centre", .unit = "mm", .min = 0.0}},
      axis{owner,
           "axis",
           Vec3::UnitZ(),
           {.help = "Shaft direction from the ball end, device frame (normalised)"}},
      pointSpacing{owner,
                   "pointSpacing",
                   d.pointSpacing,
                   {.help = "Distance between neighbouring shell points", .unit = "mm", .min = 0.0,
                    .minExclusive = true}},
      offset{owner,
             "offset",
             Vec3::Zero(),
             {.help = "Centre of the ball end in the device frame", .unit = "mm"}} {}

bool CapsuleFields::build(InitContext& context, std::vector<ShellPoint>& points, double& boundingRadius) const {
  const double R = radius.value(), r = shaftRadius.value(), L = shaftLength.value();
  const double h = pointSpacing.value();
  if (r > R) {
    context.error(shaftRadius, "the shaft (" + std::to_string(r) + " mm) must not be wider than the ball end (" +
                                   std::to_string(R) + " mm)");
    return false;
  }
  if (axis.value().norm() < 1e-9) {
    context.error(axis, "the shaft axis must not be zero");
    return false;
  }
  const Vec3 a = axis.value().normalized();
  const Quat toAxis = rotationBetween(Vec3::UnitZ(), a);
  points.clear();
  // Ball: about one point per h^2 of its area, minus the cap inside the shaft.
  const int ballCount = std::max(12, static_cast<int>(std::ceil(4 * std::numbers::pi * R * R / (h * h))));
  for (const Vec3& d : evenDirections(ballCount)) {
    const Vec3 p = R * d;
    const double along = p.dot(a);
    if (along > 0 && (p - along * a).norm() < r) continue;  // covered by the shaft
    points.push_back({p, -d});
  }
  // Shaft wall: rings from where the shaft leaves the sphere to its end.
  const double start = std::sqrt(R * R - r * r);
  const int perRing = std::max(6, static_cast<int>(std::ceil(2 * std::numbers::pi * r / h)));
  const int rings = L > start ? static_cast<int>(std::ceil((L - start) / h)) + 1 : 0;
  for (int k = 0; k < rings; ++k) {
    const double z = rings > 1 ? start + (L - start) * k / (rings - 1) : start;
    for (int i = 0; i < perRing; ++i) {
      const double phi = 2 * std::numbers::pi * (i + 0.5 * (k % 2)) / perRing;
      const Vec3 radial(std::cos(phi), std::sin(phi), 0);
      points.push_back({toAxis * (r * radial + z * Vec3::UnitZ()), toAxis * -radial});
    }
  }
  boundingRadius = std::max(R, std::sqrt(L * L + r * r));
  return true;
}

}  // namespace trephine::haptics
