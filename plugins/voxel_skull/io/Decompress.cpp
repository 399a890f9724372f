#include "plugins/voxel_skull/io/Decompress.h"

#include <zlib.h>

#include <algorithm>
#include <limits>
#include <string>

#include "plugins/voxel_skull/io/VolumeReader.h"

namespace trephine::voxel {

namespace {

constexpr uint64_t kDeflateMaxRatio = 1032;
constexpr size_t kInitialOutputBytes = size_t(1) << 16;
// zlib counts in 32-bit unsigned ints: larger buffers are fed in pieces.
constexpr uint64_t kMaxZlibChunk = std::numeric_limits<uInt>::max();

// Owns a z_stream so every exit path ends it.
class Inflater {
 public:
  explicit Inflater(const std::filesystem::path& file) : m_file(file) {
    // 15 + 32: maximum window, detect a zlib or gzip header automatically.
    if (inflateInit2(&m_stream, 15 + 32) != Z_OK) throw VolumeReadError(file, "cannot initialise zlib");
  }
  ~Inflater() { inflateEnd(&m_stream); }
  Inflater(const Inflater&) = delete;
  Inflater& operator=(const Inflater&) = delete;
  z_stream& stream() { return m_stream; }
  void reset() { inflateReset(&m_stream); }
  [[noreturn]] void fail(int code) const {
    const std::string detail = m_stream.msg ? m_stream.msg : (code == Z_MEM_ERROR ? "out of memory" : "error");
    throw VolumeReadError(m_file, "corrupt compressed data (zlib: " + detail + ")");
  }

 private:
  z_stream m_stream{};
  const std::filesystem::path& m_file;
};

bool startsGzipMember(std::span<const uint8_t> bytes) {
  return bytes.size() >= 2 && bytes[0] == 0x1f && bytes[1] == 0x8b;
}

}  // namespace

uint64_t maxInflatedSize(uint64_t compressedBytes) {
  if (compressedBytes > std::numeric_limits<uint64_t>::max() / kDeflateMaxRatio - 1024)
    return std::numeric_limits<uint64_t>::max();
  return compressedBytes * kDeflateMaxRatio + 1024;
}

InflatedBytes inflateBytes(std::span<const uint8_t> compressed, uint64_t maxBytes, const std::filesystem::path& file) {
  InflatedBytes result;
  maxBytes = std::min(maxBytes, maxInflatedSize(compressed.size()));
  if (maxBytes == 0 || compressed.empty()) return result;
  Inflater inflater(file);
  z_stream& z = inflater.stream();
  size_t inputUsed = 0;
  size_t produced = 0;
  std::vector<uint8_t>& out = result.bytes;
  out.resize(static_cast<size_t>(
      std::min<uint64_t>(maxBytes, std::max<uint64_t>(kInitialOutputBytes, 4 * compressed.size()))));
  while (produced < maxBytes) {
    if (produced == out.size()) out.resize(static_cast<size_t>(std::min<uint64_t>(maxBytes, 2 * uint64_t(out.size()))));
    const size_t inputLeft = compressed.size() - inputUsed;
    z.next_in = const_cast<Bytef*>(compressed.data() + inputUsed);
    z.avail_in = static_cast<uInt>(std::min<uint64_t>(inputLeft, kMaxZlibChunk));
    z.next_out = out.data() + produced;
    z.avail_out = static_cast<uInt>(std::min<uint64_t>(out.size() - produced, kMaxZlibChunk));
    const uInt inputOffered = z.avail_in;
    const uInt outputOffered = z.avail_out;
    const int code = inflate(&z, Z_NO_FLUSH);
    inputUsed += inputOffered - z.avail_in;
    produced += outputOffered - z.avail_out;
    if (code == Z_STREAM_END) {
      // Another gzip member may follow (files written by concatenating or by pigz).
      if (startsGzipMember(compressed.subspan(inputUsed))) {
        inflater.reset();
        continue;
      }
      result.streamEnded = true;
      break;
    }
    if (code == Z_BUF_ERROR) {
      // No progress possible: the input is exhausted before the end of the stream.
      if (inputUsed == compressed.size()) break;
      continue;
    }
    if (code != Z_OK) inflater.fail(code);
    if (inputUsed == compressed.size() && z.avail_out != 0) break;          // everything consumed, stream unfinished
    if (inputOffered == z.avail_in && outputOffered == z.avail_out) break;  // no progress: never loop forever
  }
  out.resize(produced);
  return result;
}

}  // namespace trephine::voxel
