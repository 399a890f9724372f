#include "plugins/tetra_brain/io/Inflate.h"

#include <zlib.h>

#include <algorithm>
#include <limits>

#include "plugins/tetra_brain/io/TetMeshReader.h"

namespace trephine::tetra {

namespace {

constexpr uint64_t kDeflateMaxRatio = 1032;
constexpr size_t kInitialOutputBytes = size_t(1) << 16;
// zlib counts in 32-bit unsigned ints: larger buffers are fed in pieces.
constexpr uint64_t kMaxZlibChunk = std::numeric_limits<uInt>::max();

// Owns a z_stream so that every exit path ends it.
class Inflater {
 public:
  // windowBits 15 + 32: largest window, gzip or zlib header detected automatically.
  Inflater() { m_ready = inflateInit2(&m_stream, 15 + 32) == Z_OK; }
  ~Inflater() {
    if (m_ready) inflateEnd(&m_stream);
  }
  Inflater(const Inflater&) = delete;
  Inflater& operator=(const Inflater&) = delete;
  bool ready() const { return m_ready; }
  z_stream& stream() { return m_stream; }
  void reset() { inflateReset(&m_stream); }
  std::string describe(int code) const {
    if (m_stream.msg) return m_stream.msg;
    return code == Z_MEM_ERROR ? "out of memory" : "error " + std::to_string(code);
  }

 private:
  z_stream m_stream{};
  bool m_ready = false;
};

bool startsGzipMember(std::string_view bytes) {
  return bytes.size() >= 2 && uint8_t(bytes[0]) == 0x1f && uint8_t(bytes[1]) == 0x8b;
}

// One call of inflate() on the unconsumed input and the unused output.
int inflateStep(z_stream& z, std::string_view input, size_t& used, char* out, size_t outSize, size_t& produced) {
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(input.data() + used));
  z.avail_in = static_cast<uInt>(std::min<uint64_t>(input.size() - used, kMaxZlibChunk));
  z.next_out = reinterpret_cast<Bytef*>(out + produced);
  z.avail_out = static_cast<uInt>(std::min<uint64_t>(outSize - produced, kMaxZlibChunk));
  const uInt inputOffered = z.avail_in;
  const uInt outputOffered = z.avail_out;
  const int code = inflate(&z, Z_NO_FLUSH);
  used += inputOffered - z.avail_in;
  produced += outputOffered - z.avail_out;
  return code;
}

}  // namespace

uint64_t maxInflatedSize(uint64_t compressedBytes) {
  if (compressedBytes > std::numeric_limits<uint64_t>::max() / kDeflateMaxRatio - 1024)
    return std::numeric_limits<uint64_t>::max();
  return compressedBytes * kDeflateMaxRatio + 1024;
}

std::string inflateGzip(std::string_view compressed, uint64_t maxBytes, const std::filesystem::path& file) {
  maxBytes = std::min(maxBytes, maxInflatedSize(compressed.size()));
  Inflater inflater;
  if (!inflater.ready()) throw TetMeshReadError(file, "cannot initialise zlib to decompress the gzip file");
  z_stream& z = inflater.stream();
  std::string out(static_cast<size_t>(std::min<uint64_t>(maxBytes, kInitialOutputBytes + 4 * compressed.size())), '\0');
  size_t used = 0;
  size_t produced = 0;
  while (true) {
    if (produced == out.size()) {
      if (out.size() >= maxBytes)
        throw TetMeshReadError(file, "the gzip content is larger than " + std::to_string(maxBytes) +
                                         " bytes (expected a mesh of at most 2^28 nodes and tetrahedra)");
      out.resize(static_cast<size_t>(std::min<uint64_t>(maxBytes, 2 * uint64_t(out.size()))));
    }
    const size_t usedBefore = used;
    const size_t producedBefore = produced;
    const int code = inflateStep(z, compressed, used, out.data(), out.size(), produced);
    if (code == Z_STREAM_END) {
      // Another member may follow (concatenated gzip files, pigz).
      if (startsGzipMember(compressed.substr(used))) {
        inflater.reset();
        continue;
      }
      break;
    }
    if (code != Z_OK && code != Z_BUF_ERROR)
      throw TetMeshReadError(file, "corrupt gzip data (zlib: " + inflater.describe(code) + ")");
    const bool stalled = used == usedBefore && produced == producedBefore;
    if (used == compressed.size() && (produced < out.size() || stalled))
      throw TetMeshReadError(file, "the gzip data ends before the end of the compressed stream (truncated file)");
    if (stalled) throw TetMeshReadError(file, "corrupt gzip data (zlib makes no progress)");
  }
  out.resize(produced);
  return out;
}

bool inflateExactly(std::string_view compressed, std::span<char> out, std::string& problem) {
  if (uint64_t(out.size()) > maxInflatedSize(compressed.size())) {
    problem = std::to_string(compressed.size()) + " compressed bytes cannot hold " + std::to_string(out.size());
    return false;
  }
  Inflater inflater;
  if (!inflater.ready()) {
    problem = "cannot initialise zlib";
    return false;
  }
  z_stream& z = inflater.stream();
  size_t used = 0;
  size_t produced = 0;
  // One spare byte shows a stream that holds more than expected.
  char spare = 0;
  while (true) {
    const size_t usedBefore = used;
    const size_t producedBefore = produced;
    int code = Z_OK;
    if (produced < out.size()) {
      code = inflateStep(z, compressed, used, out.data(), out.size(), produced);
    } else {
      size_t extra = 0;
      code = inflateStep(z, compressed, used, &spare, 1, extra);
      if (extra != 0) {
        problem = "the block holds more than the " + std::to_string(out.size()) + " bytes it should";
        return false;
      }
    }
    if (code == Z_STREAM_END) break;
    if (code != Z_OK && code != Z_BUF_ERROR) {
      problem = "corrupt zlib data (" + inflater.describe(code) + ")";
      return false;
    }
    if (used == usedBefore && produced == producedBefore) {
      problem = "the zlib stream ends early (after " + std::to_string(produced) + " of " + std::to_string(out.size()) +
                " bytes, without its end marker)";
      return false;
    }
  }
  if (produced != out.size()) {
    problem = "the block holds " + std::to_string(produced) + " bytes, expected " + std::to_string(out.size());
    return false;
  }
  return true;
}

}  // namespace trephine::tetra
