#pragma once
// The cube models of the deformable experiments (Table 4.1): a 200 mm cube
// cut into cells^3 cubic cells of 5 tetrahedra each, the cut alternating
// between neighbouring cells so that their faces match (7 cells: 1,715
// tetrahedra; 60 cells: 1,080,000).
#include <array>

#include "framework/data/TetMesh.h"

namespace trephine::tetra {

TetMesh makeCubeMesh(int cellsPerAxis, double size = 200.0);

// A box from `low` to `high` (mm) cut into cells[0] x cells[1] x cells[2]
// cells of 5 tetrahedra each, split as the cube's.
TetMesh makeBoxMesh(const std::array<int, 3>& cells, const Vec3& low, const Vec3& high);

}  // namespace trephine::tetra
