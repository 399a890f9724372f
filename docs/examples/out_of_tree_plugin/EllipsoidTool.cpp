#include "EllipsoidTool.h"

#include <cmath>
#include <numbers>

#include "framework/geometry/ToolSurface.h"

namespace lissajous {

void EllipsoidTool::init(trephine::InitContext&) {
  // Points of a unit sphere on a Fibonacci spiral, stretched onto the
  // ellipsoid; the inward normal there is -(x/a^2, y/b^2, z/c^2), normalised.
  const trephine::Vec3 axes = d_semiAxes.value();
  const int count = d_pointCount.value();
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  m_shell.clear();
  for (int i = 0; i < count; ++i) {
    const double z = 1 - 2 * (i + 0.5) / count, r = std::sqrt(1 - z * z);
    const trephine::Vec3 unit(r * std::cos(golden * i), r * std::sin(golden * i), z);
    const trephine::Vec3 p = unit.cwiseProduct(axes);
    const trephine::Vec3 outward = p.cwiseQuotient(axes.cwiseProduct(axes)).normalized();
    m_shell.push_back({p, -outward});
  }
}

trephine::TriangleMesh EllipsoidTool::displaySurface() const {
  // A unit sphere's surface stretched onto the ellipsoid.
  trephine::TriangleMesh surface = trephine::solidSurface({1.0, 0, 0, trephine::Vec3::UnitZ()});
  for (trephine::Vec3& v : surface.vertices) v = v.cwiseProduct(d_semiAxes.value());
  return surface;
}

}  // namespace lissajous
