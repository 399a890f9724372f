#pragma once
// Reading closed triangle surfaces, the input of tetrahedral meshing
// (`trephine mesh`): OFF, Wavefront OBJ, STL (ASCII or binary) and PLY
// (ASCII, binary little- or big-endian) and VTK XML poly data (.vtp). Polygons of more than three corners
// are split into triangles as a fan. The format is told by the content
// (OFF, ply and ASCII STL say what they are) and, for OBJ and binary STL,
// by the extension. gzip-wrapped files are read too. Coordinates are kept
// as they are in the file.
#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "framework/data/TriangleMesh.h"

namespace trephine::formats {

// Throws TetMeshReadError ("bunny.ply:12: ...", or the byte offset in a
// binary file) for anything it cannot read, and for a file with no triangle.
TriangleMesh readSurface(const std::filesystem::path& file);

}  // namespace trephine::formats
