#pragma once
// Writing a tetrahedral mesh as a VTK XML unstructured grid (.vtu), which
// ParaView and the VTU reader here open: the points (Float64, read back
// exactly), one VTK_TETRA (type 10) per tetrahedron, and the tissue labels
// as the cell array "label" when the mesh has them; zlib-compressed
// appended arrays, through the writer of the run's own VTK files.
#include <filesystem>

#include "framework/core/AtomicFile.h"
#include "framework/data/TetMesh.h"

namespace trephine::formats {

// Written through a temporary file and renamed into place (AtomicFile).
// Throws FileWriteError.
void writeVtuMesh(const TetMesh& mesh, const OutputPath& file);

// A mesh to the file its name asks for: .vtu, or Medit for .mesh and .mesh.gz.
// Throws FileWriteError (an unknown extension included).
void writeTetMeshFile(const TetMesh& mesh, const OutputPath& file);
// Whether writeTetMeshFile knows the extension of `name`.
bool isWritableTetMeshName(const std::string& name);

}  // namespace trephine::formats
