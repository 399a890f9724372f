// libFuzzer target: arbitrary bytes as a tetrahedral mesh file. The first
// byte picks the extension (.node, .mesh, .msh, .vtk or .vtu; the reader
// detects the format from the content, so the extension only matters for
// finding a TetGen pair); the rest is the file. For .node the first half of
// the rest is the node file and the second half the .ele file next to it.
// The files live in a directory of their own per process. Any crash,
// sanitizer report, hang or exception other than TetMeshReadError is a
// reader bug; so is a mesh that breaks the TetMesh contract.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "framework/formats/mesh/TetMeshReader.h"
#include "tests/fuzz/FuzzInputFiles.h"

namespace {
const std::filesystem::path& inputDirectory() { return trephine::fuzz::inputDirectory("fuzz_tet_mesh_reader"); }
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const kExtensions[] = {".node", ".mesh", ".msh", ".vtk", ".vtu"};
  const std::string extension = kExtensions[data[0] % 5];
  const std::filesystem::path file = inputDirectory() / ("input" + extension);
  const std::filesystem::path ele = inputDirectory() / "input.ele";
  const uint8_t* content = data + 1;
  const size_t contentSize = size - 1;
  if (extension == ".node") {
    const size_t half = contentSize / 2;
    trephine::fuzz::writeInputFile(file, content, half);
    trephine::fuzz::writeInputFile(ele, content + half, contentSize - half);
  } else {
    trephine::fuzz::writeInputFile(file, content, contentSize);
  }
  try {
    const trephine::TetMesh mesh = trephine::formats::readTetMesh(file);
    // A mesh that was read is usable: tetrahedra, in-range indices, finite nodes, a label per tetrahedron or none.
    if (mesh.tets.empty()) __builtin_trap();
    if (!mesh.labels.empty() && mesh.labels.size() != mesh.tets.size()) __builtin_trap();
    for (const trephine::TetIndices& tet : mesh.tets)
      for (const int32_t index : tet)
        if (index < 0 || size_t(index) >= mesh.nodes.size()) __builtin_trap();
    for (const trephine::Vec3& node : mesh.nodes)
      if (!node.allFinite()) __builtin_trap();
  } catch (const trephine::formats::TetMeshReadError& error) {
    // The message names the file before the problem.
    if (std::string(error.what()).find(": ") == std::string::npos) __builtin_trap();
  }
  std::error_code ignored;
  std::filesystem::remove(file, ignored);
  std::filesystem::remove(ele, ignored);
  return 0;
}
