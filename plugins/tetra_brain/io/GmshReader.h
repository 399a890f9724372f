#pragma once
// Gmsh .msh meshes in the legacy format ($NOD/$ELM, "version 1") and in
// format 2 ASCII ($MeshFormat 2.x 0 8, $Nodes, $Elements). Node ids may be
// any positive numbers, in any order and with gaps: they are mapped to
// positions. Linear tetrahedra (element type 4) are kept with their physical
// tag as label; other elements (points, lines, triangles, ...) are skipped.
// Sections other than nodes and elements are skipped. Binary format 2 and
// format 4 files are refused with a message saying how to re-export them.
#include <filesystem>
#include <string_view>

#include "plugins/tetra_brain/TetMesh.h"

namespace trephine::tetra {

TetMesh readGmsh(const std::filesystem::path& file, std::string_view content);

}  // namespace trephine::tetra
