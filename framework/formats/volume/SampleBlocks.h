#pragma once
// Reading the block of samples a header points to: raw bytes at an offset,
// or a zlib/gzip stream. Every size is checked against what the file can
// hold before the buffer is allocated, and short data is reported as
// "truncated: expected N bytes of data, found M".
#include <cstdint>
#include <optional>
#include <vector>

#include "framework/formats/volume/ByteSource.h"

namespace trephine::formats {

// Where the samples start in the source.
struct BlockStart {
  uint64_t offset = 0;
  // Read from the end instead: the samples are followed by exactly
  // `trailingBytes` bytes (MetaImage HeaderSize -1, NRRD byte skip -1 - n).
  bool fromEnd = false;
  uint64_t trailingBytes = 0;
};

// Appends `byteCount` raw bytes starting at `start` to `out`.
void appendRawSamples(const ByteSource& source, BlockStart start, uint64_t byteCount, std::vector<uint8_t>& out);

// Inflates the zlib/gzip stream beginning at byte `streamOffset` (to the end
// of the source, or `streamBytes` long), skips `start` in the decompressed
// bytes and appends `byteCount` bytes to `out`.
void appendCompressedSamples(const ByteSource& source, uint64_t streamOffset, std::optional<uint64_t> streamBytes,
                             BlockStart start, uint64_t byteCount, std::vector<uint8_t>& out);

// The byte offset after skipping `lines` newline-terminated lines from `offset`.
uint64_t skipLines(const ByteSource& source, uint64_t offset, int64_t lines);

}  // namespace trephine::formats
