#pragma once
// Medit / INRIA .mesh files (ASCII): keywords followed by a count and
// records, tokens separated by any white space, '#' comments, indices
// 1-based. Vertices ("x y z ref") and Tetrahedra ("a b c d ref") are read;
// the tetrahedron reference becomes its label. Every other section
// (Triangles, Edges, Corners, Ridges, Normals, ...) is skipped, whatever its
// layout, by skipping numbers up to the next keyword.
#include <filesystem>
#include <string_view>

#include "framework/data/TetMesh.h"

namespace trephine::formats {

// True when the first keyword (after comments) is MeshVersionFormatted.
bool looksLikeMedit(std::string_view content);

TetMesh readMedit(const std::filesystem::path& file, std::string_view content);

}  // namespace trephine::formats
