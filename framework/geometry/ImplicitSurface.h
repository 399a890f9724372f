#pragma once
// A target described by a signed distance: negative inside, positive outside (mm).
#include <string_view>

#include "framework/geometry/SurfaceTarget.h"

namespace trephine {

class ImplicitSurface : public SurfaceTarget {
 public:
  static constexpr std::string_view kTypeName = "ImplicitSurface";
  // Signed distance (mm) from p_W to the surface, and the outward unit normal
  // at the closest surface point. Called from the haptic loop: no allocation.
  virtual double signedDistance(const Vec3& p_W, Vec3& normal_W) const = 0;
};

}  // namespace trephine
