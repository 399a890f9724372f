#pragma once
// Gmsh .msh meshes, ASCII: format 4.1 (Gmsh's default) and 4.0 (nodes and
// elements in entity blocks), format 2 ($MeshFormat 2.x 0 8) and the legacy
// format ($NOD/$ELM, "version 1"). Node ids may be any positive numbers, in
// any order and with gaps: they are mapped to positions. Tetrahedra (element
// type 4, and the corners of the 10-node type 11) are kept with their
// physical tag as label (in format 4, the first physical tag of their volume
// entity in $Entities); other elements (points, lines, triangles, ...) are
// skipped, as are sections other than nodes, elements and entities. Binary files are refused with a message
// saying how to re-export them.
#include <filesystem>
#include <string_view>

#include "framework/data/TetMesh.h"

namespace trephine::formats {

TetMesh readGmsh(const std::filesystem::path& file, std::string_view content);

}  // namespace trephine::formats
