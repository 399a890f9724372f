#include "framework/formats/encoding/Inflate.h"

#include <zlib.h>

#include <algorithm>
#include <limits>

namespace trephine::formats {

namespace {

constexpr uint64_t kDeflateMaxRatio = 1032;
constexpr size_t kInitialOutputBytes = size_t(1) << 16;
// zlib counts in 32-bit unsigned ints: larger buffers are fed in pieces.
constexpr uint64_t kMaxZlibChunk = std::numeric_limits<uInt>::max();

// Owns a z_stream so that every exit path ends it.
class Inflater {
 public:
  Inflater() {
    // windowBits 15 + 32: largest window, gzip or zlib header detected automatically.
    if (inflateInit2(&m_stream, 15 + 32) != Z_OK) throw InflateError("cannot initialise zlib");
  }
  ~Inflater() { inflateEnd(&m_stream); }
  Inflater(const Inflater&) = delete;
  Inflater& operator=(const Inflater&) = delete;
  void reset() { inflateReset(&m_stream); }

  // One call of inflate() on the unconsumed input into out[produced, outSize).
  int step(std::span<const uint8_t> input, size_t& used, uint8_t* out, size_t outSize, size_t& produced) {
    m_stream.next_in = const_cast<Bytef*>(input.data() + used);
    m_stream.avail_in = static_cast<uInt>(std::min<uint64_t>(input.size() - used, kMaxZlibChunk));
    m_stream.next_out = out + produced;
    m_stream.avail_out = static_cast<uInt>(std::min<uint64_t>(outSize - produced, kMaxZlibChunk));
    const uInt inputOffered = m_stream.avail_in, outputOffered = m_stream.avail_out;
    const int code = inflate(&m_stream, Z_NO_FLUSH);
    used += inputOffered - m_stream.avail_in;
    produced += outputOffered - m_stream.avail_out;
    return code;
  }
  std::string describe(int code) const {
    if (m_stream.msg) return m_stream.msg;
    return code == Z_MEM_ERROR ? "out of memory" : "error " + std::to_string(code);
  }

 private:
  z_stream m_stream{};
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

Inflated inflateInto(std::span<const uint8_t> compressed, uint64_t maxBytes,
                     const std::function<uint8_t*(size_t)>& resize) {
  Inflated result;
  maxBytes = std::min(maxBytes, maxInflatedSize(compressed.size()));
  if (compressed.empty()) {
    resize(0);
    return result;
  }
  Inflater inflater;
  size_t capacity = size_t(std::min<uint64_t>(maxBytes, std::max<uint64_t>(kInitialOutputBytes, 4 * compressed.size())));
  uint8_t* out = resize(capacity);
  size_t used = 0, produced = 0;
  while (true) {
    if (produced == capacity && capacity < maxBytes) {
      capacity = size_t(std::min<uint64_t>(maxBytes, 2 * uint64_t(capacity)));
      out = resize(capacity);
    }
    const size_t usedBefore = used, producedBefore = produced;
    int code;
    if (produced < capacity) {
      code = inflater.step(compressed, used, out, capacity, produced);
    } else {
      // Full at maxBytes: one spare byte tells whether the stream holds more.
      uint8_t spare = 0;
      size_t extra = 0;
      code = inflater.step(compressed, used, &spare, 1, extra);
      if (extra != 0) {
        result.exceeded = true;
        break;
      }
    }
    if (code == Z_STREAM_END) {
      // Another member may follow (concatenated gzip files, pigz).
      if (startsGzipMember(compressed.subspan(used))) {
        inflater.reset();
        continue;
      }
      result.streamEnded = true;
      break;
    }
    if (code != Z_OK && code != Z_BUF_ERROR) throw InflateError(inflater.describe(code));
    const bool stalled = used == usedBefore && produced == producedBefore;
    if (used == compressed.size() && (produced < capacity || stalled)) break;  // input over, stream unfinished
    if (stalled) throw InflateError("zlib makes no progress");
  }
  resize(produced);
  result.size = produced;
  return result;
}

std::optional<std::string> inflateExactly(std::span<const uint8_t> compressed, std::span<uint8_t> out) {
  if (uint64_t(out.size()) > maxInflatedSize(compressed.size()))
    return std::to_string(compressed.size()) + " compressed bytes cannot hold " + std::to_string(out.size());
  Inflated inflated;
  try {
    inflated = inflateInto(compressed, out.size(), [&](size_t) { return out.data(); });
  } catch (const InflateError& e) {
    return "corrupt zlib data (" + std::string(e.what()) + ")";
  }
  if (inflated.exceeded) return "the block holds more than the " + std::to_string(out.size()) + " bytes it should";
  if (!inflated.streamEnded)
    return "the zlib stream ends early (after " + std::to_string(inflated.size) + " of " +
           std::to_string(out.size()) + " bytes, without its end marker)";
  if (inflated.size != out.size())
    return "the block holds " + std::to_string(inflated.size) + " bytes, expected " + std::to_string(out.size());
  return std::nullopt;
}

WholeStream inflateWhole(std::span<const uint8_t> compressed, uint64_t maxBytes) {
  WholeStream whole;
  try {
    const Inflated inflated = inflateInto(compressed, maxBytes, [&](size_t n) {
      whole.bytes.resize(n);
      return whole.bytes.data();
    });
    if (inflated.exceeded)
      whole.problem = WholeStream::Problem::kTooLarge;
    else if (!inflated.streamEnded)
      whole.problem = WholeStream::Problem::kTruncated;
  } catch (const InflateError& e) {
    whole.problem = WholeStream::Problem::kCorrupt;
    whole.zlibReason = e.what();
  }
  return whole;
}

}  // namespace trephine::formats
