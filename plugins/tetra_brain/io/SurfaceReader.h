#pragma once
// Reading closed triangle surfaces, the input of tetrahedral meshing
// (`trephine mesh`): OFF, Wavefront OBJ, STL (ASCII or binary) and PLY
// (ASCII, binary little- or big-endian). Polygons of more than three corners
// are split into triangles as a fan. The format is told by the content
// (OFF, ply and ASCII STL say what they are) and, for OBJ and binary STL,
// by the extension. gzip-wrapped files are read too. Coordinates are kept
// as they are in the file.
#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "framework/math/Math.h"

namespace trephine::tetra {

struct TriangleSurface {
  std::vector<Vec3> vertices;
  std::vector<std::array<int32_t, 3>> triangles;  // 0-based vertex indices
};

// Throws TetMeshReadError ("bunny.ply:12: ...", or the byte offset in a
// binary file) for anything it cannot read, and for a file with no triangle.
TriangleSurface readSurface(const std::filesystem::path& file);

}  // namespace trephine::tetra
