#pragma once
// VTK legacy files (.vtk) holding an unstructured grid: "# vtk DataFile
// Version x.y", a title, ASCII or BINARY (big-endian, as VTK writes it), then
// DATASET UNSTRUCTURED_GRID with POINTS, CELLS (the classic "n i j k ..."
// layout, or the OFFSETS/CONNECTIVITY layout of version 5.1) and CELL_TYPES.
// Only tetrahedra are kept: VTK_TETRA (type 10), and the corners of
// VTK_QUADRATIC_TETRA (24). An integer cell array named like a label
// (SCALARS or FIELD array "label", "tissue", ...) becomes the labels; other
// attribute data is skipped.
#include <filesystem>
#include <string_view>

#include "framework/data/TetMesh.h"

namespace trephine::formats {

bool looksLikeVtkLegacy(std::string_view content);

TetMesh readVtkLegacy(const std::filesystem::path& file, std::string_view content);

}  // namespace trephine::formats
