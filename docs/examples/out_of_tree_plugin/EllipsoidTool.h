#pragma once
// A tool of one's own: an ellipsoid sampled by a pointshell, moved by a
// device. It implements the framework's ShellTool, so GodObjectProxy moves
// it against any target (a VoxelSkull, a TetraBrain) on the native back-end,
// point by point, and Embree's takes it point by point too. What a tool
// declares:
//   - its shell: points on its surface in the tool frame, each with the
//     unit normal pointing into the tool;
//   - its leading radius: how far its surface reaches ahead of the reference
//     point, which the proxy's sweep stops at the target's surface. For an
//     ellipsoid the smallest semi-axis: with the largest, the sweep would
//     stop the tool short of the surface wherever its short side leads; with
//     the smallest, a longer side that meets the surface first is found by
//     the contact that follows the sweep;
//   - its bounding radius: every shell point lies within it (the largest
//     semi-axis);
//   - the solid it samples, for back-ends that test solids (Bullet): the
//     default, a sphere of the leading radius, would be wrong, so it
//     describes none and Bullet refuses it at load;
//   - what it looks like, for VtkExporter's files and the viewer: the
//     default draws the solid, so it gives its own surface (a sphere's,
//     stretched onto the ellipsoid).
#include <string_view>
#include <vector>

#include "framework/devices/HapticDevice.h"
#include "framework/geometry/ShellTool.h"

namespace lissajous {

class EllipsoidTool final : public trephine::Component, public trephine::ShellTool {
 public:
  static constexpr std::string_view kTypeName = "EllipsoidTool";

  void init(trephine::InitContext& context) override;

  std::span<const trephine::ShellPoint> shellPoints() const override { return m_shell; }
  trephine::HapticDevice& device() const override { return *l_device; }
  trephine::Pose toolPose(const trephine::Pose& X_WD) const override { return X_WD; }
  double leadingRadius() const override { return d_semiAxes.value().minCoeff(); }
  double boundingRadius() const override { return d_semiAxes.value().maxCoeff(); }
  trephine::ToolSolid solid() const override { return {0, 0, 0, trephine::Vec3::UnitZ()}; }
  trephine::TriangleMesh displaySurface() const override;

 private:
  trephine::Link<trephine::HapticDevice> l_device{
      this, "device", {.help = "Device that moves the tool", .required = true}};
  trephine::Field<trephine::Vec3> d_semiAxes{this,
                                             "semiAxes",
                                             trephine::Vec3(4, 2, 2),
                                             {.help = "Semi-axes along the tool's x, y and z",
                                              .unit = "mm",
                                              .min = 0.0,
                                              .minExclusive = true}};
  trephine::Field<int> d_pointCount{
      this, "pointCount", 400, {.help = "Shell points (a Fibonacci spiral)", .min = 20.0, .max = 100000.0}};
  std::vector<trephine::ShellPoint> m_shell;
};

}  // namespace lissajous
