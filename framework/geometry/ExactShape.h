#pragma once
// The shape a target was generated from, when it is known exactly: a phantom
// defined by an implicit function. Studies measure a back-end's penetration
// and normal against it (`trephine study`); nothing on the haptic path uses it.
#include <functional>
#include <string_view>

#include "framework/math/Math.h"

namespace trephine {

// Level-set function of a solid in the world frame (mm): negative inside,
// positive outside, zero on the surface. It need not be a distance, but it
// must change sign across the surface and nowhere else.
using LevelSet = std::function<double(const Vec3&)>;

// An interface, implemented by targets next to Component.
class ExactShapeSource {
 public:
  static constexpr std::string_view kTypeName = "ExactShapeSource";
  virtual ~ExactShapeSource() = default;

  // The exact solid, or an empty function when the target was read from data
  // (a scan, a mesh file) and no exact shape exists.
  virtual LevelSet exactShape() const = 0;
};

}  // namespace trephine
