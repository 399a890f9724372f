#include "plugins/haptics/PointshellTool.h"

#include "framework/core/Lifecycle.h"
#include "framework/geometry/ShellSampling.h"

namespace trephine::haptics {

void PointshellTool::init(InitContext& context) {
  if (d_pointCount.value() > 0 && d_angleStep.isSet()) {
    context.error(d_pointCount, "give either pointCount or angleStep, not both");
    return;
  }
  const std::vector<Vec3> directions =
      d_pointCount.value() > 0 ? evenDirections(d_pointCount.value()) : angleStepDirections(d_angleStep.value());
  m_points.clear();
  m_points.reserve(directions.size());
  for (const Vec3& d : directions) m_points.push_back({d_radius.value() * d, -d});
}

Pose PointshellTool::toolPose(const Pose& X_WD) const {
  return {X_WD.position + X_WD.orientation * d_offset.value(), X_WD.orientation};
}

void PointshellTool::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"shell_points", static_cast<double>(m_points.size())});
}

}  // namespace trephine::haptics
