#pragma once
// The cube models of the deformable experiments (Table 4.1): a 200 mm cube
// cut into cells^3 cubic cells of 5 tetrahedra each, the cut alternating
// between neighbouring cells so that their faces match (7 cells: 1,715
// tetrahedra; 60 cells: 1,080,000).
#include "plugins/tetra_brain/TetMesh.h"

namespace trephine::tetra {

TetMesh makeCubeMesh(int cellsPerAxis, double size = 200.0);

}  // namespace trephine::tetra
