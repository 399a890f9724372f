#pragma once
// Reading tetrahedral meshes from the file formats that surgical simulation
// data sets come in: TetGen .node + .ele, Medit .mesh, Gmsh .msh (ASCII
// 4.1, 4.0, 2.x and the legacy format), VTK legacy .vtk (ASCII or big-endian binary) and VTK XML
// .vtu (ascii, inline base64 or appended raw or base64 binary, optionally
// zlib-compressed).
//
// The format is recognised from the content, never from the extension: data
// sets mislabel files (a VTK XML file named .vtk). gzip-wrapped files are
// decompressed transparently. Coordinates are taken as millimetres as they
// are in the file; no unit conversion is made. Only linear tetrahedra are
// kept; other elements (points, lines, triangles, ...) are skipped. Geometry
// is not validated here (orientation, degenerate or inverted tetrahedra):
// that is TetTopology's job.
#include <filesystem>
#include <stdexcept>
#include <string>

#include "framework/data/TetMesh.h"
#include "framework/formats/FileReadError.h"

namespace trephine::formats {

// A file that cannot be read as a tetrahedral mesh.
using TetMeshReadError = FileReadError;

// Reads a tetrahedral mesh. For TetGen, `file` may be the .node file, the
// .ele file (each possibly .gz) or their common base name without extension:
// the other file of the pair is found next to it. Labels are filled when the
// format carries one per tetrahedron (TetGen's first element attribute,
// Medit's reference, Gmsh's physical tag, a VTK cell array named like
// "label", "tissue" or "gmsh:physical"). Throws TetMeshReadError for
// anything it cannot read, including a file without tetrahedra.
TetMesh readTetMesh(const std::filesystem::path& file);

}  // namespace trephine::formats
