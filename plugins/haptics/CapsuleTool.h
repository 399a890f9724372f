#pragma once
// A burr on a shaft (CapsuleShape.h): the ball is a spinning burr that drills
// a drillable target. One component is all a new tool shape needs: see ShellTool.
#include <vector>

#include "framework/devices/HapticDevice.h"
#include "framework/geometry/ShellTool.h"
#include "plugins/haptics/BurrFields.h"
#include "plugins/haptics/CapsuleShape.h"

namespace trephine::haptics {

class CapsuleTool final : public Component, public ShellTool {
 public:
  static constexpr std::string_view kTypeName = "CapsuleTool";

  void init(InitContext& context) override { d_shape.build(context, m_points, m_boundingRadius); }
  void reportCounters(std::vector<Counter>& counters) const override {
    counters.push_back({"shell_points", static_cast<double>(m_points.size())});
  }

  std::span<const ShellPoint> shellPoints() const override { return m_points; }
  HapticDevice& device() const override { return *l_device; }
  Pose toolPose(const Pose& X_WD) const override { return d_shape.toolPose(X_WD); }
  double leadingRadius() const override { return d_shape.radius.value(); }
  CuttingBurr cuttingBurr() const override { return d_burr.value(); }
  double boundingRadius() const override { return m_boundingRadius; }
  ToolSolid solid() const override { return d_shape.solid(); }

 private:
  Link<HapticDevice> l_device{this, "device", {.help = "Device that moves the tool", .required = true}};
  CapsuleFields d_shape{this, {2.5, 1.0, 20.0, 0.4}};
  BurrFields d_burr{this};

  std::vector<ShellPoint> m_points;
  double m_boundingRadius = 0;
};

}  // namespace trephine::haptics
