#pragma once
// The shape of a tool with a ball end on a shaft (a burr on its shaft, an
// aspirator's tube, a forceps' tip): a sphere of `radius` at the tool's
// reference point and a cylinder of `shaftRadius` running `shaftLength` along
// `axis` (device frame) from the ball's centre, covered by shell points (the
// ball except where the shaft covers it, and the shaft wall), so a shaft
// touching an edge pushes back too. The fields are declared once here for
// every tool of this shape (CapsuleTool, AspiratorTool, BipolarForceps), with
// each tool's own defaults.
#include <string>
#include <vector>

#include "framework/core/Field.h"
#include "framework/geometry/ShellTool.h"

namespace trephine {
class InitContext;
}

namespace trephine::haptics {

struct CapsuleDefaults {
  double radius, shaftRadius, shaftLength;  // mm
  double pointSpacing;                      // mm
};

struct CapsuleFields {
  CapsuleFields(FieldOwner* owner, const CapsuleDefaults& defaults);

  // The shell (tool frame) and the radius every point lies within; an error
  // at the field that is wrong, and false, when the shape cannot be built.
  bool build(InitContext& context, std::vector<ShellPoint>& points, double& boundingRadius) const;
  Pose toolPose(const Pose& X_WD) const {
    return {X_WD.position + X_WD.orientation * offset.value(), X_WD.orientation};
  }
  ToolSolid solid() const {
    return {radius.value(), shaftRadius.value(), shaftLength.value(), axis.value().normalized()};
  }

  Field<double> radius;
  Field<double> shaftRadius;
  Field<double> shaftLength;
  Field<Vec3> axis;
  Field<double> pointSpacing;
  Field<Vec3> offset;
};

}  // namespace trephine::haptics
