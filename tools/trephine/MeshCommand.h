#pragma once
// `trephine mesh SURFACE --out OUT [--tets N | --size S]`: tetrahedral
// meshing of a closed surface (OFF, OBJ, STL, PLY) or of an implicit ball,
// with CGAL Mesh_3.
#include "tools/trephine/CommandLine.h"

namespace trephine::cli {

int meshCommand(const Arguments& arguments);

}  // namespace trephine::cli
