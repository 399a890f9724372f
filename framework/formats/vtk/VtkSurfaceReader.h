#pragma once
// The triangles of a VTK XML poly data file (.vtp), in any encoding VTK
// writes (ascii, inline base64, appended raw or base64, zlib-compressed or
// not, either byte order, 32- or 64-bit headers): what `trephine view`
// simplifies before a browser draws a skull's surface blocks, and a surface
// `trephine mesh` reads. Polygons of other than three corners, vertices,
// lines and strips are skipped.
#include <filesystem>
#include <string_view>

#include "framework/data/TriangleMesh.h"
#include "framework/formats/FileReadError.h"

namespace trephine::formats {

using VtkReadError = FileReadError;

// The surface of `content`, the text of `file`; it may hold no triangle.
TriangleMesh readVtkPolyData(const std::filesystem::path& file, std::string_view content);
// The same, read from the file.
TriangleMesh readVtkPolyDataSurface(const std::filesystem::path& file);

}  // namespace trephine::formats
