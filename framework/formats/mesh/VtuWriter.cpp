#include "framework/formats/mesh/VtuWriter.h"

#include <string>

#include "framework/formats/mesh/MeditWriter.h"
#include "framework/formats/vtk/VtkXml.h"

namespace trephine::formats {

void writeVtuMesh(const TetMesh& mesh, const OutputPath& file) {
  if (mesh.tets.empty()) throw FileWriteError(file.path(), "the mesh has no tetrahedra");
  VtkTetGrid grid;
  grid.points = mesh.nodes;
  grid.tets = mesh.tets;
  grid.labels = mesh.labels;
  grid.precision = PointPrecision::kFloat64;
  writeTetGrid(grid, file);
}

bool isWritableTetMeshName(const std::string& name) {
  return name.ends_with(".vtu") || name.ends_with(".mesh") || name.ends_with(".mesh.gz");
}

void writeTetMeshFile(const TetMesh& mesh, const OutputPath& file) {
  const std::string name = file.relative().filename().string();
  if (name.ends_with(".vtu")) return writeVtuMesh(mesh, file);
  if (name.ends_with(".mesh") || name.ends_with(".mesh.gz")) return writeMeditMesh(mesh, file);
  throw FileWriteError(file.path(), "unknown mesh format: expected a name ending in .vtu, .mesh or .mesh.gz");
}

}  // namespace trephine::formats
