#pragma once
// The whole content of a mesh file in memory, gunzipped when the file starts
// with the gzip magic bytes (1f 8b) whatever its name. Mesh files are read
// whole: every format needs most of the file, and parsing from memory is what
// makes a 150k-tetrahedron brain load in a fraction of a second.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace trephine::formats {

// Largest file (or decompressed content) accepted: far above any mesh of
// 2^28 nodes and tetrahedra, far below what would exhaust a workstation by
// accident. 16 GiB.
constexpr uint64_t kMaxContentBytes = uint64_t(1) << 34;

// The file's bytes, decompressed if gzip-wrapped. Throws TetMeshReadError for
// a missing, unreadable, non-regular or empty file and for corrupt gzip data.
std::string readFileContent(const std::filesystem::path& file);

bool startsWithGzipMagic(std::string_view bytes);

}  // namespace trephine::formats
