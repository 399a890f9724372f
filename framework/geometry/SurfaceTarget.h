#pragma once
// Something a tool can touch: a skull volume, a brain mesh, an analytic plane.
// Scripted devices use these queries to aim at a target's surface whatever its
// geometry, so the same scripted scene works on any skull or brain.
#include <optional>
#include <string_view>

#include "framework/core/Component.h"
#include "framework/math/Math.h"

namespace trephine {

struct SurfaceHit {
  Vec3 point;       // mm, world frame
  Vec3 normal;      // unit, pointing out of the target
  double distance;  // mm along the ray
};

// An interface, implemented by components next to Component:
//   class AnalyticPlane final : public Component, public ImplicitSurface { ... };
class SurfaceTarget {
 public:
  static constexpr std::string_view kTypeName = "SurfaceTarget";
  virtual ~SurfaceTarget() = default;

  // World-frame bounds of the target (mm).
  virtual Box3 bounds() const = 0;
  // First entry into the target along origin + s * direction, 0 <= s <= maxDistance
  // (direction is unit). Used off the haptic path (set-up, scripted paths).
  virtual std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const = 0;
};

}  // namespace trephine
