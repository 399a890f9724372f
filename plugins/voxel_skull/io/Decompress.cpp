#include "plugins/voxel_skull/io/Decompress.h"

#include <string>

#include "plugins/voxel_skull/io/VolumeReader.h"

namespace trephine::voxel {

InflatedBytes inflateBytes(std::span<const uint8_t> compressed, uint64_t maxBytes, const std::filesystem::path& file) {
  InflatedBytes result;
  try {
    const Inflated inflated = inflateInto(compressed, maxBytes, [&](size_t n) {
      result.bytes.resize(n);
      return result.bytes.data();
    });
    result.streamEnded = inflated.streamEnded;
  } catch (const InflateError& e) {
    throw VolumeReadError(file, std::string("corrupt compressed data (zlib: ") + e.what() + ")");
  }
  return result;
}

}  // namespace trephine::voxel
