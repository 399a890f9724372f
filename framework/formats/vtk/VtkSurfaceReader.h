#pragma once
// Reading back the triangles of a VTK XML poly data file (.vtp) whose arrays
// are appended raw: zlib blocks or not, UInt32 or UInt64 headers, Float32 or
// Float64 points, Int32 or Int64 connectivity (what this project and VTK's
// own writers produce by default). For `trephine view`, which simplifies a
// skull's surface blocks before a browser draws them. Polygons of other than
// three corners, vertices, lines and strips are skipped.
#include <array>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "framework/data/TriangleMesh.h"

namespace trephine::vtk {

// A file that is not such poly data; the message names the file and what was
// expected there.
class VtkReadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

TriangleMesh readTriangleSurface(const std::filesystem::path& file);

}  // namespace trephine::vtk
