#pragma once
// Generated meshes for scenes (file="phantom:...") and `trephine phantom`:
// cube?cells=22&size=200 (Table 4.1) and brain?tets=22000 (Table 4.2 sizes).
#include <string>

#include "framework/geometry/ExactShape.h"
#include "framework/data/TetMesh.h"

namespace trephine::tetra {

// Throws std::invalid_argument naming the unknown phantom, key or bad value.
TetMesh makeTetPhantom(const std::string& specification);
// The solid the phantom's mesh approximates (mm, negative inside): the cube
// exactly, the brain's implicit surface (its boundary nodes lie on it).
// Throws as makeTetPhantom.
LevelSet tetPhantomShape(const std::string& specification);
std::string tetPhantomHelp();

}  // namespace trephine::tetra
