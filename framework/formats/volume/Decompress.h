#pragma once
// Inflating the zlib and gzip streams of volume files (MetaImage
// CompressedData, NRRD gzip encoding, .nii.gz) through the framework's
// capped inflater, with errors that name the file.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

#include "framework/formats/encoding/Inflate.h"

namespace trephine::formats {

// Inflates a whole zlib or gzip stream of at most `maxBytes` bytes (the
// output grows with what is decompressed). The stream must reach its end
// marker: only there does zlib check the Adler-32 (zlib) or CRC-32 and length
// (gzip) trailer, which is what tells changed bytes that still decode from
// the data that was written. Throws VolumeReadError naming `file` for a
// corrupt stream, a failed checksum, a stream that ends early (truncated) or
// one that holds more than `maxBytes` (`what` names the bytes expected, as in
// "the 4096 bytes of samples the header describes").
// `samples`, when given: the bytes of data the stream should hold after
// `skipped` ones, for the message of a truncated stream.
std::vector<uint8_t> inflateVolumeData(std::span<const uint8_t> compressed, uint64_t maxBytes,
                                       const std::filesystem::path& file, const char* what,
                                       std::optional<uint64_t> samples = std::nullopt, uint64_t skipped = 0);

}  // namespace trephine::formats
