#pragma once
// Writing a tetrahedral mesh as a VTK XML unstructured grid (.vtu, ASCII),
// which ParaView and the VTU reader here open: the points, one VTK_TETRA
// (type 10) per tetrahedron, and the tissue labels as the cell array
// "label" when the mesh has them. Coordinates in their shortest exact form.
#include <filesystem>

#include "framework/core/AtomicFile.h"
#include "plugins/tetra_brain/TetMesh.h"

namespace trephine::tetra {

// Written through a temporary file and renamed into place (AtomicFile).
// Throws FileWriteError.
void writeVtuMesh(const TetMesh& mesh, const std::filesystem::path& file);

// A mesh to the file its name asks for: .vtu, or Medit for .mesh and .mesh.gz.
// Throws FileWriteError (an unknown extension included).
void writeTetMeshFile(const TetMesh& mesh, const std::filesystem::path& file);
// Whether writeTetMeshFile knows the extension of `name`.
bool isWritableTetMeshName(const std::string& name);

}  // namespace trephine::tetra
