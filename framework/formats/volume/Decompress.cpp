#include "framework/formats/volume/Decompress.h"

#include <algorithm>
#include <string>

#include "framework/formats/volume/VolumeReader.h"

namespace trephine::formats {

std::vector<uint8_t> inflateVolumeData(std::span<const uint8_t> compressed, uint64_t maxBytes,
                                  const std::filesystem::path& file, const char* what,
                                  std::optional<uint64_t> samples, uint64_t skipped) {
  WholeStream whole = inflateWhole(compressed, maxBytes);
  std::vector<uint8_t>& bytes = whole.bytes;
  if (whole.problem == WholeStream::Problem::kCorrupt)
    throw VolumeReadError(file, "corrupt compressed data (zlib: " + whole.zlibReason + ")");
  if (whole.problem == WholeStream::Problem::kTooLarge)
    throw VolumeReadError(file, "corrupt compressed data: the stream holds more than " + std::string(what) + " (" +
                                    std::to_string(maxBytes) + " bytes)");
  if (whole.problem == WholeStream::Problem::kTruncated) {
    const std::string unfinished = "the compressed stream ends without its end marker and checksum";
    if (samples) {
      const uint64_t found = bytes.size() > skipped ? std::min<uint64_t>(bytes.size() - skipped, *samples) : 0;
      throw VolumeReadError(file, "truncated: expected " + std::to_string(*samples) + " bytes of data, found " +
                                      std::to_string(found) + " (" + unfinished + ")");
    }
    throw VolumeReadError(file, "truncated: " + unfinished + ", after " + std::to_string(bytes.size()) + " bytes");
  }
  return std::move(whole.bytes);
}

}  // namespace trephine::formats
