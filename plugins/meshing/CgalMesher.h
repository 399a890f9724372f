#pragma once
// The tetrahedral mesher on CGAL Mesh_3 (CgalMesher.cpp, the project's only
// CGAL code), which the plugin provides as the framework's TetMesher.
#include <memory>

#include "framework/meshing/TetMeshing.h"

namespace trephine::meshing {

std::shared_ptr<TetMesher> makeCgalTetMesher();

}  // namespace trephine::meshing
