#pragma once
// What a tool looks like, for the files and the viewer that draw it: a
// triangle surface in the tool frame. By default the solid its shell
// samples (ToolSolid): the burr's sphere and, on a shaft, the shaft's
// cylinder closed at its end; a tool of another shape declares its own
// (ShellTool::displaySurface).
#include "framework/data/TriangleMesh.h"
#include "framework/geometry/ShellTool.h"

namespace trephine {

// The sphere of solid.radius at the origin and, when solid.shaftLength > 0,
// a cylinder of solid.shaftRadius from the origin along solid.shaftAxis,
// capped at its end; `segments` around (at least 6).
TriangleMesh solidSurface(const ToolSolid& solid, int segments = 24);

}  // namespace trephine
