#include "plugins/voxel_skull/io/Decompress.h"

#include <algorithm>
#include <string>

#include "plugins/voxel_skull/io/VolumeReader.h"

namespace trephine::voxel {

std::vector<uint8_t> inflateWhole(std::span<const uint8_t> compressed, uint64_t maxBytes,
                                  const std::filesystem::path& file, const char* what,
                                  std::optional<uint64_t> samples, uint64_t skipped) {
  std::vector<uint8_t> bytes;
  Inflated inflated;
  try {
    inflated = inflateInto(compressed, maxBytes, [&](size_t n) {
      bytes.resize(n);
      return bytes.data();
    });
  } catch (const InflateError& e) {
    throw VolumeReadError(file, std::string("corrupt compressed data (zlib: ") + e.what() + ")");
  }
  if (inflated.exceeded)
    throw VolumeReadError(file, "corrupt compressed data: the stream holds more than " + std::string(what) + " (" +
                                    std::to_string(maxBytes) + " bytes)");
  if (!inflated.streamEnded) {
    const std::string unfinished = "the compressed stream ends without its end marker and checksum";
    if (samples) {
      const uint64_t found = bytes.size() > skipped ? std::min<uint64_t>(bytes.size() - skipped, *samples) : 0;
      throw VolumeReadError(file, "truncated: expected " + std::to_string(*samples) + " bytes of data, found " +
                                      std::to_string(found) + " (" + unfinished + ")");
    }
    throw VolumeReadError(file, "truncated: " + unfinished + ", after " + std::to_string(bytes.size()) + " bytes");
  }
  return bytes;
}

}  // namespace trephine::voxel
