#pragma once
// VTK XML unstructured grids (.vtu): <VTKFile type="UnstructuredGrid"> with
// one or more <Piece>s, each with <Points> (3 components, any numeric type)
// and <Cells> (connectivity, offsets and types arrays). Arrays may be ascii,
// inline base64 binary, or in <AppendedData> (raw or base64; the default of
// VTK's and ParaView's writers), zlib-compressed or not, in either byte order
// and with 32- or 64-bit headers. Only tetrahedra are kept (VTK_TETRA, type
// 10, and the corners of VTK_QUADRATIC_TETRA, 24); an integer <CellData>
// array named like a label ("label", "tissue", "gmsh:physical", ...) becomes
// the labels.
#include <filesystem>
#include <string_view>

#include "framework/data/TetMesh.h"

namespace trephine::formats {

TetMesh readVtu(const std::filesystem::path& file, std::string_view content);

}  // namespace trephine::formats
