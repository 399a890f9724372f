#include "framework/formats/volume/SampleBlocks.h"

#include <algorithm>
#include <string>

#include "framework/formats/volume/Decompress.h"
#include "framework/formats/volume/VolumeReader.h"

namespace trephine::formats {

namespace {

[[noreturn]] void throwTruncated(const ByteSource& source, uint64_t expected, uint64_t found) {
  throw VolumeReadError(source.path(), "truncated: expected " + std::to_string(expected) + " bytes of data, found " +
                                           std::to_string(found));
}

// Grows `out` by `count` bytes, after the caller has checked they exist.
std::span<uint8_t> extend(std::vector<uint8_t>& out, uint64_t count) {
  const size_t old = out.size();
  out.resize(old + static_cast<size_t>(count));
  return std::span<uint8_t>(out).subspan(old);
}

}  // namespace

void appendRawSamples(const ByteSource& source, BlockStart start, uint64_t byteCount, std::vector<uint8_t>& out) {
  const uint64_t size = source.size();
  uint64_t offset = start.offset;
  if (start.fromEnd) {
    if (size < start.trailingBytes || size - start.trailingBytes < byteCount)
      throwTruncated(source, byteCount, size > start.trailingBytes ? size - start.trailingBytes : 0);
    offset = size - start.trailingBytes - byteCount;
  } else if (offset > size || size - offset < byteCount) {
    throwTruncated(source, byteCount, offset < size ? size - offset : 0);
  }
  source.read(offset, extend(out, byteCount));
}

void appendCompressedSamples(const ByteSource& source, uint64_t streamOffset, std::optional<uint64_t> streamBytes,
                             BlockStart start, uint64_t byteCount, std::vector<uint8_t>& out) {
  const uint64_t size = source.size();
  if (streamOffset > size) throwTruncated(source, byteCount, 0);
  uint64_t available = size - streamOffset;
  if (streamBytes) {
    if (*streamBytes > available)
      throw VolumeReadError(source.path(), "truncated: expected " + std::to_string(*streamBytes) +
                                               " bytes of compressed data, found " + std::to_string(available));
    available = *streamBytes;
  }
  const uint64_t skipped = start.fromEnd ? 0 : start.offset;
  const uint64_t needed = skipped + byteCount;
  if (needed < byteCount || needed > maxInflatedSize(available)) {
    throw VolumeReadError(source.path(), "truncated: " + std::to_string(available) +
                                             " bytes of compressed data cannot hold the expected " +
                                             std::to_string(byteCount) + " bytes");
  }
  const std::vector<uint8_t> compressed = source.readClipped(streamOffset, available);
  // The whole stream is inflated, to its checksum: with a skip from the end
  // it may hold anything before the samples; otherwise exactly the skipped
  // bytes and the samples.
  const uint64_t limit = start.fromEnd ? maxInflatedSize(available) : needed;
  const std::vector<uint8_t> bytes =
      inflateVolumeData(compressed, limit, source.path(), start.fromEnd ? "deflate can hold" : "the samples the header describes",
                   byteCount, skipped);
  uint64_t first = skipped;
  if (start.fromEnd) {
    if (bytes.size() < start.trailingBytes || bytes.size() - start.trailingBytes < byteCount)
      throwTruncated(source, byteCount, bytes.size() > start.trailingBytes ? bytes.size() - start.trailingBytes : 0);
    first = bytes.size() - start.trailingBytes - byteCount;
  } else if (bytes.size() < needed) {
    throwTruncated(source, byteCount, bytes.size() > skipped ? bytes.size() - skipped : 0);
  }
  std::span<uint8_t> target = extend(out, byteCount);
  std::copy_n(bytes.begin() + static_cast<ptrdiff_t>(first), static_cast<size_t>(byteCount), target.begin());
}

uint64_t skipLines(const ByteSource& source, uint64_t offset, int64_t lines) {
  constexpr uint64_t kChunk = uint64_t(1) << 16;
  int64_t left = lines;
  while (left > 0) {
    const std::vector<uint8_t> chunk = source.readClipped(offset, kChunk);
    if (chunk.empty())
      throw VolumeReadError(source.path(), "truncated: the file ends before the " + std::to_string(lines) +
                                               " lines to skip before the data");
    for (size_t n = 0; n < chunk.size(); ++n) {
      if (chunk[n] == '\n' && --left == 0) return offset + n + 1;
    }
    offset += chunk.size();
  }
  return offset;
}

}  // namespace trephine::formats
