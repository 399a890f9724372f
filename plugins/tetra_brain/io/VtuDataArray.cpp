#include "plugins/tetra_brain/io/VtuDataArray.h"

#include <optional>
#include <span>
#include <string>
#include <type_traits>

#include "plugins/tetra_brain/io/Base64.h"
#include "plugins/tetra_brain/io/Inflate.h"
#include "plugins/tetra_brain/io/NumberType.h"
#include "plugins/tetra_brain/io/ReadChecks.h"
#include "plugins/tetra_brain/io/TetMeshReader.h"
#include "plugins/tetra_brain/io/TextCursor.h"

namespace trephine::tetra {

namespace {

class ArrayDecoder {
 public:
  ArrayDecoder(const VtuArray& array, const VtuEncoding& encoding, const std::filesystem::path& file)
      : m_array(array), m_encoding(encoding), m_file(file) {}

  template <typename Out>
  std::vector<Out> read(int64_t count) {
    const std::optional<NumberType> type = xmlNumberType(m_array.type);
    if (!type)
      fail("type " + quoteForMessage(m_array.type) + " is not supported, expected Int8 ... UInt64, Float32 or Float64");
    if (std::is_same_v<Out, int64_t> && !isInteger(*type))
      fail("type " + quoteForMessage(m_array.type) + ", expected an integer type (Int32, Int64, UInt8, ...)");
    if (count < 0 || count > kMaxArrayValues)
      fail(std::to_string(count) + " values expected, more than the " + std::to_string(kMaxArrayValues) + " supported");
    if (m_array.format == "ascii") return readAscii<Out>(count);
    if (m_array.format == "binary") {
      std::vector<Out> values;
      decodeNumbers(binaryBytes(uint64_t(count) * byteSize(*type)), *type, m_encoding.bigEndian, values);
      return values;
    }
    if (m_array.format == "appended")
      fail(
          "format=\"appended\" (data in <AppendedData>) is not supported, expected \"ascii\" or \"binary\" "
          "(inline base64; in ParaView save with \"Data Mode: Ascii or Binary\")");
    fail("format " + quoteForMessage(m_array.format) + ", expected \"ascii\" or \"binary\"");
  }

 private:
  [[noreturn]] void fail(const std::string& problem, size_t line = 0) const {
    throw TetMeshReadError(m_file, line ? line : m_array.line,
                           "DataArray \"" + std::string(m_array.name) + "\": " + problem);
  }

  template <typename Out>
  std::vector<Out> readAscii(int64_t count) {
    // Each value takes at least one character and one separator.
    if (uint64_t(count) > m_array.text.size() / 2 + 1)
      fail("the text is too short for the " + std::to_string(count) + " values expected (truncated?)");
    TextCursor text(m_array.text, m_file);
    std::vector<Out> values;
    values.reserve(size_t(count));
    for (int64_t i = 0; i < count; ++i) {
      const std::string_view token = text.next();
      if (token.empty()) fail("holds " + std::to_string(i) + " values, expected " + std::to_string(count));
      std::optional<Out> value;
      if constexpr (std::is_same_v<Out, double>)
        value = parseReal(token);
      else
        value = parseInteger(token);
      if (!value)
        fail("value " + std::to_string(i) + " is " + quoteForMessage(token) + ", expected a number", lineOf(text));
      values.push_back(*value);
    }
    if (!text.atEnd()) fail("holds more than the " + std::to_string(count) + " values expected", lineOf(text));
    return values;
  }

  size_t lineOf(const TextCursor& text) const { return m_array.line + text.line() - 1; }

  uint64_t headerValue(std::string_view bytes, size_t index) const {
    const size_t size = m_encoding.header64 ? 8 : 4;
    std::vector<int64_t> value;
    decodeNumbers(bytes.substr(index * size, size), m_encoding.header64 ? NumberType::kUInt64 : NumberType::kUInt32,
                  m_encoding.bigEndian, value);
    return uint64_t(value.at(0));
  }

  // The packed values (exactly `expectedBytes`) of a binary array.
  std::string binaryBytes(uint64_t expectedBytes) {
    std::string decoded;
    size_t badOffset = 0;
    if (!decodeBase64(m_array.text, decoded, badOffset))
      fail("the base64 text has an invalid character at offset " + std::to_string(badOffset) +
           (badOffset < m_array.text.size() ? " (" + quoteForMessage(m_array.text.substr(badOffset, 1)) + ")"
                                            : std::string()));
    return m_encoding.zlib ? inflateBlocks(decoded, expectedBytes) : uncompressed(decoded, expectedBytes);
  }

  std::string uncompressed(const std::string& decoded, uint64_t expectedBytes) const {
    const size_t headerSize = m_encoding.header64 ? 8 : 4;
    if (decoded.size() < headerSize) fail("the binary data has no byte-count header (truncated)");
    const uint64_t bytes = headerValue(decoded, 0);
    if (bytes != expectedBytes)
      fail("the header gives " + std::to_string(bytes) + " bytes of data, expected " + std::to_string(expectedBytes));
    if (decoded.size() - headerSize < bytes)
      fail("the binary data holds " + std::to_string(decoded.size() - headerSize) + " bytes, expected " +
           std::to_string(bytes) + " (truncated)");
    return decoded.substr(headerSize, size_t(bytes));
  }

  // Compressed arrays: [blocks, block size, last block size, compressed size of each block] then the blocks.
  std::string inflateBlocks(const std::string& decoded, uint64_t expectedBytes) const {
    const size_t headerSize = m_encoding.header64 ? 8 : 4;
    if (decoded.size() < 3 * headerSize) fail("the compressed data has no block header (truncated)");
    const uint64_t blocks = headerValue(decoded, 0);
    const uint64_t blockSize = headerValue(decoded, 1);
    const uint64_t lastSize = headerValue(decoded, 2);
    if (blocks > decoded.size() / headerSize - 3)
      fail("the header lists " + std::to_string(blocks) + " compressed blocks, more than the data holds (truncated?)");
    // The total without overflow: every block but the last is full; a last size of 0 means full too.
    const uint64_t last = lastSize == 0 ? blockSize : lastSize;
    const bool fits =
        blocks == 0 || (last <= blockSize && (blocks - 1 == 0 || blockSize <= expectedBytes / (blocks - 1)));
    const uint64_t total = blocks == 0 ? 0 : (blocks - 1) * blockSize + last;
    if (!fits || total != expectedBytes)
      fail("the block header describes " +
           (fits ? std::to_string(total) : std::string("more than ") + std::to_string(expectedBytes)) +
           " bytes of data, expected " + std::to_string(expectedBytes));
    uint64_t offset = (3 + blocks) * headerSize;
    uint64_t compressedTotal = 0;
    for (uint64_t b = 0; b < blocks; ++b) {
      const uint64_t size = headerValue(decoded, size_t(3 + b));
      if (size > decoded.size() - offset - compressedTotal)
        fail("compressed block " + std::to_string(b) + " needs " + std::to_string(size) + " bytes, only " +
             std::to_string(decoded.size() - offset - compressedTotal) + " remain (truncated)");
      compressedTotal += size;
    }
    if (maxInflatedSize(compressedTotal) < expectedBytes)
      fail(std::to_string(compressedTotal) + " compressed bytes cannot hold the " + std::to_string(expectedBytes) +
           " bytes expected");
    std::string out(size_t(expectedBytes), '\0');
    uint64_t produced = 0;
    for (uint64_t b = 0; b < blocks; ++b) {
      const uint64_t size = headerValue(decoded, size_t(3 + b));
      const uint64_t outSize = b + 1 == blocks ? last : blockSize;
      const std::span<const uint8_t> block(reinterpret_cast<const uint8_t*>(decoded.data()) + offset, size_t(size));
      if (auto problem = inflateExactly(block, {reinterpret_cast<uint8_t*>(out.data()) + produced, size_t(outSize)}))
        fail("compressed block " + std::to_string(b) + ": " + *problem);
      offset += size;
      produced += outSize;
    }
    return out;
  }

  const VtuArray& m_array;
  const VtuEncoding& m_encoding;
  const std::filesystem::path& m_file;
};

}  // namespace

std::vector<double> readVtuReals(const VtuArray& array, int64_t count, const VtuEncoding& encoding,
                                 const std::filesystem::path& file) {
  return ArrayDecoder(array, encoding, file).read<double>(count);
}

std::vector<int64_t> readVtuIntegers(const VtuArray& array, int64_t count, const VtuEncoding& encoding,
                                     const std::filesystem::path& file) {
  return ArrayDecoder(array, encoding, file).read<int64_t>(count);
}

}  // namespace trephine::tetra
