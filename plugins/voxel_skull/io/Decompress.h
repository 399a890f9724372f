#pragma once
// Inflating the zlib and gzip streams of volume files (MetaImage
// CompressedData, NRRD gzip encoding, .nii.gz) through the framework's
// capped inflater, with errors that name the file.
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "framework/compression/Inflate.h"

namespace trephine::voxel {

struct InflatedBytes {
  std::vector<uint8_t> bytes;
  bool streamEnded = false;  // false: the input ran out (truncated) or maxBytes was reached first
};

// Inflates a zlib or gzip stream into at most `maxBytes` bytes (the output
// grows with what is decompressed). Throws VolumeReadError naming `file` for a
// corrupt stream.
InflatedBytes inflateBytes(std::span<const uint8_t> compressed, uint64_t maxBytes, const std::filesystem::path& file);

}  // namespace trephine::voxel
