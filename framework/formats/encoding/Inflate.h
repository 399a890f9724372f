#pragma once
// Inflating zlib and gzip streams for the file readers (compressed MetaImage,
// NRRD and NIfTI volumes; gzipped mesh files and zlib blocks of VTK XML
// arrays), with a hard cap on the output so that a corrupt or malicious
// stream cannot make a reader allocate more than the file could hold. zlib
// itself stays inside Inflate.cpp.
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace trephine::formats {

// deflate never compresses better than about 1032:1, so n compressed bytes
// cannot hold more than this: lets readers refuse impossible sizes up front.
uint64_t maxInflatedSize(uint64_t compressedBytes);

// A stream zlib rejects; the message is zlib's reason ("invalid stored block lengths").
class InflateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Inflated {
  size_t size = 0;           // bytes produced
  bool streamEnded = false;  // the stream's end marker was reached
  bool exceeded = false;     // the stream holds more than maxBytes (stopped there)
};

// Inflates a zlib or gzip stream (the wrapper is detected; concatenated gzip
// members are joined, other trailing bytes ignored as gunzip does) into a
// buffer of the caller's: `resize(n)` makes it n bytes and returns its data.
// It grows with what is produced, never to maxBytes up front, and ends
// resized to the bytes produced. streamEnded false and exceeded false: the
// input ended first (a truncated file). Throws InflateError for corrupt data.
Inflated inflateInto(std::span<const uint8_t> compressed, uint64_t maxBytes,
                     const std::function<uint8_t*(size_t)>& resize);

// A whole stream inflated to its end marker, where zlib checks the Adler-32
// (zlib) or CRC-32 and length (gzip) trailer: what tells changed bytes that
// still decode from the data that was written. `problem` says why not.
struct WholeStream {
  enum class Problem { kNone, kCorrupt, kTooLarge, kTruncated };
  std::vector<uint8_t> bytes;  // what was produced (up to the problem)
  Problem problem = Problem::kNone;
  std::string zlibReason;      // kCorrupt: zlib's words
};
// Never more than `maxBytes` (kTooLarge past it); grows with the output.
WholeStream inflateWhole(std::span<const uint8_t> compressed, uint64_t maxBytes);

// Inflates one stream that must produce exactly out.size() bytes; otherwise
// says why (corrupt, ends early, holds more or fewer bytes).
std::optional<std::string> inflateExactly(std::span<const uint8_t> compressed, std::span<uint8_t> out);

}  // namespace trephine::formats
