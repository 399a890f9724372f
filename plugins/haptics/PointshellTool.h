#pragma once
// A spherical burr of `radius` covered by a pointshell: the thesis's tool. The
// points come from the angle-step scheme (angleStep, degrees) or, when
// pointCount > 0, from an even-area distribution of that many points.
#include <vector>

#include "framework/devices/HapticDevice.h"
#include "framework/geometry/ShellTool.h"
#include "plugins/haptics/BurrFields.h"

namespace trephine::haptics {

class PointshellTool final : public Component, public ShellTool {
 public:
  static constexpr std::string_view kTypeName = "PointshellTool";

  void init(InitContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;

  std::span<const ShellPoint> shellPoints() const override { return m_points; }
  HapticDevice& device() const override { return *l_device; }
  Pose toolPose(const Pose& X_WD) const override;
  double leadingRadius() const override { return d_radius.value(); }
  CuttingBurr cuttingBurr() const override { return d_burr.value(); }
  double boundingRadius() const override { return d_radius.value(); }

 private:
  Link<HapticDevice> l_device{this, "device", {.help = "Device that moves the tool", .required = true}};
  Field<double> d_radius{this, "radius", 2.5, {.help = "Burr radius", .unit = "mm", .min = 0.0, .minExclusive = true}};
  Field<double> d_angleStep{this,
                            "angleStep",
                            10.0,
                            {.help = "Step of both sphere angles in the angle-step scheme (10 gives 614 points)",
                             .unit = "deg",
                             .min = 1.0,
                             .max = 90.0}};
  Field<int> d_pointCount{
      this,
      "pointCount",
      0,
      {.help = "Number of evenly spread points; 0 uses angleStep instead", .min = 0.0, .max = 100000.0}};
  Field<Vec3> d_offset{this, "offset", Vec3::Zero(), {.help = "Burr centre in the device frame", .unit = "mm"}};
  BurrFields d_burr{this};

  std::vector<ShellPoint> m_points;
};

}  // namespace trephine::haptics
