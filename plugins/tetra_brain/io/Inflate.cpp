#include "plugins/tetra_brain/io/Inflate.h"

#include <span>

#include "plugins/tetra_brain/io/TetMeshReader.h"

namespace trephine::tetra {

std::string inflateGzip(std::string_view compressed, uint64_t maxBytes, const std::filesystem::path& file) {
  std::string out;
  Inflated inflated;
  try {
    const std::span<const uint8_t> bytes(reinterpret_cast<const uint8_t*>(compressed.data()), compressed.size());
    inflated = inflateInto(bytes, maxBytes, [&](size_t n) {
      out.resize(n);
      return reinterpret_cast<uint8_t*>(out.data());
    });
  } catch (const InflateError& e) {
    throw TetMeshReadError(file, std::string("corrupt gzip data (zlib: ") + e.what() + ")");
  }
  if (inflated.exceeded)
    throw TetMeshReadError(file, "the gzip content is larger than " + std::to_string(maxBytes) +
                                     " bytes (expected a mesh of at most 2^28 nodes and tetrahedra)");
  if (!inflated.streamEnded)
    throw TetMeshReadError(file, "the gzip data ends before the end of the compressed stream (truncated file)");
  return out;
}

}  // namespace trephine::tetra
