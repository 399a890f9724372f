// libFuzzer target: arbitrary bytes as a triangle surface file. The first
// byte picks the extension (.off, .obj, .stl or .ply: the reader takes OBJ
// and binary STL by their extension; or .vtp, VTK XML poly data, which
// trephine view reads with trephine::formats::readVtkPolyDataSurface); the rest is the file.
// Any crash, sanitizer report, hang or exception other than TetMeshReadError
// (VtkReadError for .vtp) is a reader bug; so is a surface that breaks the
// trephine::TriangleMesh contract.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "framework/formats/vtk/VtkSurfaceReader.h"
#include "framework/formats/surface/SurfaceReader.h"
#include "framework/formats/mesh/TetMeshReader.h"
#include "tests/fuzz/FuzzInputFiles.h"

namespace {
const std::filesystem::path& inputDirectory() { return trephine::fuzz::inputDirectory("fuzz_surface_reader"); }
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const kExtensions[] = {".off", ".obj", ".stl", ".ply", ".vtp"};
  const std::filesystem::path file = inputDirectory() / (std::string("input") + kExtensions[data[0] % 5]);
  trephine::fuzz::writeInputFile(file, data + 1, size - 1);
  if (data[0] % 5 == 4) {
    try {
      const trephine::TriangleMesh surface = trephine::formats::readVtkPolyDataSurface(file);
      for (const auto& triangle : surface.triangles)
        for (const int32_t index : triangle)
          if (index < 0 || size_t(index) >= surface.vertices.size()) __builtin_trap();
    } catch (const trephine::formats::FileReadError& error) {
      if (std::string(error.what()).find(": ") == std::string::npos) __builtin_trap();
    }
    std::error_code ignored;
    std::filesystem::remove(file, ignored);
    return 0;
  }
  try {
    const trephine::TriangleMesh surface = trephine::formats::readSurface(file);
    if (surface.triangles.empty()) __builtin_trap();
    for (const auto& triangle : surface.triangles)
      for (const int32_t index : triangle)
        if (index < 0 || size_t(index) >= surface.vertices.size()) __builtin_trap();
    for (const trephine::Vec3& vertex : surface.vertices)
      if (!vertex.allFinite()) __builtin_trap();
  } catch (const trephine::formats::TetMeshReadError& error) {
    if (std::string(error.what()).find(": ") == std::string::npos) __builtin_trap();
  }
  std::error_code ignored;
  std::filesystem::remove(file, ignored);
  return 0;
}
