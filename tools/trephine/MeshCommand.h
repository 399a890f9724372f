#pragma once
// `trephine mesh INPUT --out OUT [--labels L,...] [--tets N | --size S]`:
// tetrahedral meshing of a closed surface (OFF, OBJ, STL, PLY), an implicit
// ball, or a labelled image (a segmentation; each tetrahedron keeps its
// label), with CGAL Mesh_3 (the meshing plugin).
#include "tools/trephine/CommandLine.h"

namespace trephine::cli {

int meshCommand(const Arguments& arguments);

}  // namespace trephine::cli
