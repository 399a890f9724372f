#include "plugins/haptics/CapsuleTool.h"

#include <cmath>
#include <numbers>

#include "framework/core/Lifecycle.h"
#include "framework/geometry/ShellSampling.h"

namespace trephine::haptics {

void CapsuleTool::init(InitContext& context) {
  const double R = d_radius.value(), r = d_shaftRadius.value(), L = d_shaftLength.value();
  const double h = d_pointSpacing.value();
  if (r > R) {
    context.error(d_shaftRadius, "the shaft (" + std::to_string(r) + " mm) must not be wider than the burr (" +
                                     std::to_string(R) + " mm)");
    return;
  }
  if (d_axis.value().norm() < 1e-9) {
    context.error(d_axis, "the shaft axis must not be zero");
    return;
  }
  const Vec3 axis = d_axis.value().normalized();
  const Quat toAxis = rotationBetween(Vec3::UnitZ(), axis);
  m_points.clear();
  // Burr: about one point per h^2 of its area, minus the cap inside the shaft.
  const int burrCount = std::max(12, static_cast<int>(std::ceil(4 * std::numbers::pi * R * R / (h * h))));
  for (const Vec3& d : evenDirections(burrCount)) {
    const Vec3 p = R * d;
    const double along = p.dot(axis);
    if (along > 0 && (p - along * axis).norm() < r) continue;  // covered by the shaft
    m_points.push_back({p, -d});
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
      m_points.push_back({toAxis * (r * radial + z * Vec3::UnitZ()), toAxis * -radial});
    }
  }
  m_boundingRadius = std::max(R, std::sqrt(L * L + r * r));
}

Pose CapsuleTool::toolPose(const Pose& X_WD) const {
  return {X_WD.position + X_WD.orientation * d_offset.value(), X_WD.orientation};
}

void CapsuleTool::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"shell_points", static_cast<double>(m_points.size())});
}

}  // namespace trephine::haptics
