#pragma once
// Inflating zlib and gzip streams (MetaImage CompressedData, NRRD gzip
// encoding, .nii.gz files) with a hard cap on the output, so a corrupt or
// malicious stream cannot make us allocate more than the caller expects.
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace trephine::voxel {

// zlib's deflate never compresses better than about 1032:1, so a stream of n
// bytes cannot hold more than this many bytes of data: used to refuse
// impossible sizes before inflating anything.
uint64_t maxInflatedSize(uint64_t compressedBytes);

struct InflatedBytes {
  std::vector<uint8_t> bytes;
  bool streamEnded = false;  // false: the input ran out (truncated) or maxBytes was reached first
};

// Inflates a zlib or gzip stream (the wrapper is auto-detected; concatenated
// gzip members are joined) into at most `maxBytes` bytes. The output buffer
// grows with what is actually decompressed, never to maxBytes up front.
// Throws VolumeReadError naming `file` for a corrupt stream.
InflatedBytes inflateBytes(std::span<const uint8_t> compressed, uint64_t maxBytes, const std::filesystem::path& file);

}  // namespace trephine::voxel
