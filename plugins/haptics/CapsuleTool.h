#pragma once
// A burr on a shaft: a sphere of `radius` at the tool's reference point and a
// cylinder of `shaftRadius` running `shaftLength` along `axis` (device frame)
// from the burr centre. Shell points cover the sphere (except where the shaft
// covers it) and the shaft wall, so a shaft touching a bone edge pushes back too.
// One component is all a new tool shape needs: see ShellTool.
#include <vector>

#include "framework/devices/HapticDevice.h"
#include "framework/geometry/ShellTool.h"
#include "plugins/haptics/BurrFields.h"

namespace trephine::haptics {

class CapsuleTool final : public Component, public ShellTool {
 public:
  static constexpr std::string_view kTypeName = "CapsuleTool";

  void init(InitContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;

  std::span<const ShellPoint> shellPoints() const override { return m_points; }
  HapticDevice& device() const override { return *l_device; }
  Pose toolPose(const Pose& X_WD) const override;
  double leadingRadius() const override { return d_radius.value(); }
  CuttingBurr cuttingBurr() const override { return d_burr.value(); }
  double boundingRadius() const override { return m_boundingRadius; }
  ToolSolid solid() const override {
    return {d_radius.value(), d_shaftRadius.value(), d_shaftLength.value(), d_axis.value().normalized()};
  }

 private:
  Link<HapticDevice> l_device{this, "device", {.help = "Device that moves the tool", .required = true}};
  Field<double> d_radius{this, "radius", 2.5, {.help = "Burr radius", .unit = "mm", .min = 0.0, .minExclusive = true}};
  Field<double> d_shaftRadius{
      this,
      "shaftRadius",
      1.0,
      {.help = "Shaft radius (at most the burr radius)", .unit = "mm", .min = 0.0, .minExclusive = true}};
  Field<double> d_shaftLength{
      this, "shaftLength", 20.0, {.help = "Shaft length from the burr centre", .unit = "mm", .min = 0.0}};
  Field<Vec3> d_axis{this, "axis", Vec3::UnitZ(), {.help = "Shaft direction from the burr, device frame (normalised)"}};
  Field<double> d_pointSpacing{
      this,
      "pointSpacing",
      0.4,
      {.help = "Distance between neighbouring shell points", .unit = "mm", .min = 0.0, .minExclusive = true}};
  Field<Vec3> d_offset{this, "offset", Vec3::Zero(), {.help = "Burr centre in the device frame", .unit = "mm"}};
  BurrFields d_burr{this};

  std::vector<ShellPoint> m_points;
  double m_boundingRadius = 0;
};

}  // namespace trephine::haptics
