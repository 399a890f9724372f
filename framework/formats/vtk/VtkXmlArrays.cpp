#include "framework/formats/vtk/VtkXmlArrays.h"

#include <algorithm>
#include <optional>
#include <span>
#include <string>
#include <type_traits>

#include "framework/formats/encoding/Base64.h"
#include "framework/formats/encoding/Inflate.h"
#include "framework/formats/encoding/NumberType.h"
#include "framework/formats/mesh/ReadChecks.h"
#include "framework/formats/mesh/TetMeshReader.h"
#include "framework/formats/mesh/TextCursor.h"

namespace trephine::formats {

namespace {

class ArrayDecoder {
 public:
  ArrayDecoder(const VtkXmlArray& array, const VtkXmlEncoding& encoding, const std::filesystem::path& file)
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
    if (m_array.format == "binary" || m_array.format == "appended") {
      const uint64_t expectedBytes = uint64_t(count) * byteSize(*type);
      std::vector<Out> values;
      decodeNumbers(m_array.format == "binary" ? inlineBytes(expectedBytes) : appendedBytes(expectedBytes), *type,
                    m_encoding.bigEndian, values);
      return values;
    }
    fail("format " + quoteForMessage(m_array.format) + ", expected \"ascii\", \"binary\" or \"appended\"");
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

  size_t headerSize() const { return m_encoding.header64 ? 8 : 4; }

  // The packed values (exactly `expectedBytes`) of an inline binary array.
  std::string inlineBytes(uint64_t expectedBytes) const {
    const std::string decoded = base64Decoded(m_array.text, 0);
    return m_encoding.zlib ? inflateBlocks(decoded, expectedBytes) : uncompressed(decoded, expectedBytes);
  }

  // The same from <AppendedData>, at the array's offset. Raw data is read in
  // place. Base64 data is decoded chunk by chunk, as VTK encodes it: the
  // header and the values as one chunk (or two), or (compressed) the block
  // header and the blocks as two; each chunk's length follows from its header.
  std::string appendedBytes(uint64_t expectedBytes) const {
    if (!m_encoding.hasAppended) fail("format=\"appended\" but the file has no <AppendedData>");
    if (m_array.offset > m_encoding.appended.size())
      fail("offset " + std::to_string(m_array.offset) + " is beyond the " + std::to_string(m_encoding.appended.size()) +
           " bytes of <AppendedData>");
    const std::string_view rest = m_encoding.appended.substr(size_t(m_array.offset));
    if (!m_encoding.appendedBase64)
      return m_encoding.zlib ? inflateBlocks(rest, expectedBytes) : uncompressed(rest, expectedBytes);
    if (!m_encoding.zlib) {
      // One chunk (VTK), or the header as a chunk of its own: a 4- or 8-byte
      // header alone always ends in padding.
      const uint64_t headerChars = base64Length(headerSize());
      if (rest.size() < headerChars || rest[size_t(headerChars) - 1] != '=')
        return uncompressed(base64Chunk(rest, headerSize() + expectedBytes), expectedBytes);
      std::string decoded = base64Chunk(rest, headerSize());
      decoded += base64Chunk(rest.substr(size_t(headerChars)), expectedBytes);
      return uncompressed(decoded, expectedBytes);
    }
    const std::string start = base64Chunk(rest, 3 * headerSize());
    const uint64_t blocks = headerValue(start, 0);
    if (blocks > rest.size() / headerSize())
      fail("the header lists " + std::to_string(blocks) + " compressed blocks, more than the data holds (truncated?)");
    const uint64_t headerBytes = (3 + blocks) * headerSize();
    std::string decoded = base64Chunk(rest, headerBytes);
    uint64_t compressedBytes = 0;
    for (uint64_t b = 0; b < blocks; ++b) {
      compressedBytes += headerValue(decoded, size_t(3 + b));
      if (compressedBytes > rest.size()) fail("the compressed blocks need more bytes than the data holds (truncated)");
    }
    decoded += base64Chunk(rest.substr(size_t(base64Length(headerBytes))), compressedBytes);
    return inflateBlocks(decoded, expectedBytes);
  }

  static uint64_t base64Length(uint64_t bytes) { return (bytes + 2) / 3 * 4; }

  // The first `bytes` bytes of the base64 chunk at the start of `text`.
  std::string base64Chunk(std::string_view text, uint64_t bytes) const {
    const uint64_t length = base64Length(bytes);
    if (length > text.size())
      fail("the base64 data from offset " + std::to_string(m_array.offset) + " has " + std::to_string(text.size()) +
           " characters left, expected at least " + std::to_string(length) + " (truncated)");
    std::string decoded = base64Decoded(text.substr(0, size_t(length)), m_array.offset);
    decoded.resize(std::min(decoded.size(), size_t(bytes)));
    return decoded;
  }

  // `offset`: where `text` starts in the array's data, for the message.
  std::string base64Decoded(std::string_view text, uint64_t offset) const {
    std::string decoded;
    size_t badOffset = 0;
    if (!decodeBase64(text, decoded, badOffset))
      fail("the base64 text has an invalid character at offset " + std::to_string(offset + badOffset) +
           (badOffset < text.size() ? " (" + quoteForMessage(text.substr(badOffset, 1)) + ")" : std::string()));
    return decoded;
  }

  std::string uncompressed(std::string_view decoded, uint64_t expectedBytes) const {
    if (decoded.size() < headerSize()) fail("the binary data has no byte-count header (truncated)");
    const uint64_t bytes = headerValue(decoded, 0);
    if (bytes != expectedBytes)
      fail("the header gives " + std::to_string(bytes) + " bytes of data, expected " + std::to_string(expectedBytes));
    if (decoded.size() - headerSize() < bytes)
      fail("the binary data holds " + std::to_string(decoded.size() - headerSize()) + " bytes, expected " +
           std::to_string(bytes) + " (truncated)");
    return std::string(decoded.substr(headerSize(), size_t(bytes)));
  }

  // Compressed arrays: [blocks, block size, last block size, compressed size of each block] then the blocks.
  std::string inflateBlocks(std::string_view decoded, uint64_t expectedBytes) const {
    if (decoded.size() < 3 * headerSize()) fail("the compressed data has no block header (truncated)");
    const uint64_t blocks = headerValue(decoded, 0);
    const uint64_t blockSize = headerValue(decoded, 1);
    const uint64_t lastSize = headerValue(decoded, 2);
    if (blocks > decoded.size() / headerSize() - 3)
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
    uint64_t offset = (3 + blocks) * headerSize();
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

  const VtkXmlArray& m_array;
  const VtkXmlEncoding& m_encoding;
  const std::filesystem::path& m_file;
};

}  // namespace

std::vector<double> readVtkXmlReals(const VtkXmlArray& array, int64_t count, const VtkXmlEncoding& encoding,
                                 const std::filesystem::path& file) {
  return ArrayDecoder(array, encoding, file).read<double>(count);
}

std::vector<int64_t> readVtkXmlIntegers(const VtkXmlArray& array, int64_t count, const VtkXmlEncoding& encoding,
                                     const std::filesystem::path& file) {
  return ArrayDecoder(array, encoding, file).read<int64_t>(count);
}

}  // namespace trephine::formats
