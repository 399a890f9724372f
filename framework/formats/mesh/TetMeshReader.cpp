#include "framework/formats/mesh/TetMeshReader.h"

#include <algorithm>
#include <system_error>

#include "framework/formats/mesh/FileContent.h"
#include "framework/formats/mesh/FormatDetection.h"
#include "framework/formats/mesh/GmshReader.h"
#include "framework/formats/mesh/MeditReader.h"
#include "framework/formats/mesh/TetGenReader.h"
#include "framework/formats/mesh/TextCursor.h"
#include "framework/formats/mesh/VtkLegacyReader.h"
#include "framework/formats/mesh/VtuReader.h"

namespace trephine::formats {

namespace {

TetMesh readContent(const std::filesystem::path& file, std::string content) {
  switch (detectMeshFormat(content)) {
    case MeshFormat::kTetGen:
      return readTetGen(file, std::move(content));
    case MeshFormat::kMedit:
      return readMedit(file, content);
    case MeshFormat::kGmsh:
      return readGmsh(file, content);
    case MeshFormat::kVtkLegacy:
      return readVtkLegacy(file, content);
    case MeshFormat::kVtu:
      return readVtu(file, content);
    case MeshFormat::kMeditBinary:
      throw TetMeshReadError(file, "binary Medit (.meshb) files are not supported, expected an ASCII .mesh");
    case MeshFormat::kUnknown:
      break;
  }
  throw TetMeshReadError(file, "not a recognised tetrahedral mesh: the content starts with " +
                                   quoteForMessage(content.substr(0, 24)) +
                                   " (expected TetGen .node/.ele, Medit .mesh, Gmsh .msh ASCII (4.1, 4.0, 2.x or "
                                   "legacy), VTK legacy .vtk or VTK XML .vtu)");
}

}  // namespace

TetMesh readTetMesh(const std::filesystem::path& file) {
  std::error_code error;
  if (!std::filesystem::exists(file, error)) {
    // A TetGen pair named by its base name ("brain_gm_wm" for brain_gm_wm.node + .ele.gz).
    if (const auto nodeFile = findTetGenNodeForBase(file)) return readTetMesh(*nodeFile);
  }
  TetMesh mesh = readContent(file, readFileContent(file));
  if (mesh.tets.empty()) throw TetMeshReadError(file, "the mesh has no tetrahedra (expected at least one)");
  return mesh;
}

}  // namespace trephine::formats
