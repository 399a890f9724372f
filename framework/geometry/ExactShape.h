#pragma once
// The shape a target was generated from, when it is known exactly: a phantom
// defined by an implicit function. Studies measure a back-end's penetration
// and normal against it (`trephine study`); nothing on the haptic path uses it.
#include <functional>
#include <memory>
#include <optional>
#include <string_view>

#include "framework/data/DensityVolume.h"
#include "framework/math/Math.h"

namespace trephine {

// Level-set function of a solid in the world frame (mm): negative inside,
// positive outside, zero on the surface. It need not be a distance, but it
// must change sign across the surface and nowhere else.
using LevelSet = std::function<double(const Vec3&)>;

// A scan as its file holds it, before any resampling a setting asks for, and
// the isovalue that bounds its solid (denser is inside).
struct ScanAsRead {
  std::shared_ptr<const DensityVolume> volume;
  double isovalue = 0;
};

// An interface, implemented by targets next to Component.
class ExactShapeSource {
 public:
  static constexpr std::string_view kTypeName = "ExactShapeSource";
  virtual ~ExactShapeSource() = default;

  // The exact solid, or an empty function when the target was read from data
  // (a scan, a mesh file) and no exact shape exists.
  virtual LevelSet exactShape() const = 0;
  // A target read from a scan: the scan, read again from its file (throws
  // what the reader throws). A study's reference is then the isosurface of
  // its trilinearly interpolated density. Nothing otherwise.
  virtual std::optional<ScanAsRead> scanAsRead() const { return std::nullopt; }
};

}  // namespace trephine
