#pragma once
// Deflating bytes into one zlib stream, for the writers of compressed files
// (the zlib blocks of VTK XML arrays). zlib itself stays in Deflate.cpp.
#include <cstdint>
#include <span>
#include <string>

namespace trephine::formats {

// The zlib stream of `bytes` at zlib's `level` (1 fastest to 9 smallest).
std::string deflateBytes(std::span<const uint8_t> bytes, int level = 6);

}  // namespace trephine::formats
