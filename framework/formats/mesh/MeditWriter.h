#pragma once
// Writing a tetrahedral mesh as a Medit / INRIA .mesh file (ASCII), the
// format the readers here, Gmsh, MMG, TetGen and CGAL all understand:
// MeshVersionFormatted 2, Dimension 3, Vertices (x y z 0), Tetrahedra
// (1-based corners, the label as reference, 0 without labels), End.
// Coordinates are written in their shortest exact form, so readTetMesh gives
// back bit-identical nodes.
#include <filesystem>
#include <stdexcept>
#include <string>

#include "framework/core/AtomicFile.h"
#include "framework/data/TetMesh.h"

namespace trephine::formats {

// A mesh that cannot be written: the message starts with the file, then says
// what failed ("out/brain.mesh: cannot create ...: No such file or directory").
using TetMeshWriteError = FileWriteError;

// Writes `mesh` to `file`, gzip-compressed when the name ends in .gz. The file
// is written under a temporary name in the same directory and renamed into
// place once complete, so a failed write leaves neither a partial file nor the
// temporary one. Refuses meshes the readers would refuse (no tetrahedra,
// corners out of range, non-finite coordinates, a label count that is not the
// tetrahedron count). Throws TetMeshWriteError.
void writeMeditMesh(const TetMesh& mesh, const OutputPath& file);

}  // namespace trephine::formats
