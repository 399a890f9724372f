#include "plugins/tetra_brain/io/VtuWriter.h"

#include <charconv>
#include <cmath>
#include <string>

#include "plugins/tetra_brain/io/MeditWriter.h"

namespace trephine::tetra {

namespace {
void appendNumber(std::string& out, double value) {
  char digits[32];
  const auto result = std::to_chars(digits, digits + sizeof digits, value);
  out.append(digits, result.ptr);
}
void appendNumber(std::string& out, int64_t value) {
  char digits[24];
  const auto result = std::to_chars(digits, digits + sizeof digits, value);
  out.append(digits, result.ptr);
}
}  // namespace

void writeVtuMesh(const TetMesh& mesh, const std::filesystem::path& file) {
  if (mesh.tets.empty()) throw FileWriteError(file, "the mesh has no tetrahedra");
  if (!mesh.labels.empty() && mesh.labels.size() != mesh.tets.size())
    throw FileWriteError(file, "the mesh has " + std::to_string(mesh.labels.size()) + " labels for " +
                                   std::to_string(mesh.tets.size()) + " tetrahedra");
  for (const Vec3& p : mesh.nodes)
    if (!p.allFinite()) throw FileWriteError(file, "a node has a non-finite coordinate");
  for (const TetIndices& t : mesh.tets)
    for (int32_t n : t)
      if (n < 0 || size_t(n) >= mesh.nodeCount()) throw FileWriteError(file, "a tetrahedron names a missing node");
  AtomicFile out(file);
  std::string text;
  const auto flush = [&] {
    out.write(text);
    text.clear();
  };
  text += "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n";
  text += "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" + std::to_string(mesh.nodeCount()) + "\" NumberOfCells=\"" +
          std::to_string(mesh.tetCount()) + "\">\n";
  text += "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const Vec3& p : mesh.nodes) {
    for (int i = 0; i < 3; ++i) {
      appendNumber(text, p[i]);
      text += i < 2 ? ' ' : '\n';
    }
    if (text.size() > (1 << 20)) flush();
  }
  text += "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const TetIndices& t : mesh.tets) {
    for (int i = 0; i < 4; ++i) {
      appendNumber(text, int64_t(t[i]));
      text += i < 3 ? ' ' : '\n';
    }
    if (text.size() > (1 << 20)) flush();
  }
  text += "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (size_t i = 0; i < mesh.tetCount(); ++i) {
    appendNumber(text, int64_t(4 * (i + 1)));
    text += '\n';
    if (text.size() > (1 << 20)) flush();
  }
  text += "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (size_t i = 0; i < mesh.tetCount(); ++i) {
    text += "10\n";
    if (text.size() > (1 << 20)) flush();
  }
  text += "</DataArray>\n</Cells>\n";
  if (!mesh.labels.empty()) {
    text += "<CellData Scalars=\"label\">\n<DataArray type=\"Int32\" Name=\"label\" format=\"ascii\">\n";
    for (int32_t label : mesh.labels) {
      appendNumber(text, int64_t(label));
      text += '\n';
      if (text.size() > (1 << 20)) flush();
    }
    text += "</DataArray>\n</CellData>\n";
  }
  text += "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  flush();
  out.commit();
}

bool isWritableTetMeshName(const std::string& name) {
  return name.ends_with(".vtu") || name.ends_with(".mesh") || name.ends_with(".mesh.gz");
}

void writeTetMeshFile(const TetMesh& mesh, const std::filesystem::path& file) {
  const std::string name = file.filename().string();
  if (name.ends_with(".vtu")) return writeVtuMesh(mesh, file);
  if (name.ends_with(".mesh") || name.ends_with(".mesh.gz")) return writeMeditMesh(mesh, file);
  throw FileWriteError(file, "unknown mesh format: expected a name ending in .vtu, .mesh or .mesh.gz");
}

}  // namespace trephine::tetra
