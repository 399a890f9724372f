#include "framework/formats/volume/MetaImageReader.h"

#include <bit>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "framework/core/Strings.h"
#include "framework/formats/volume/HeaderText.h"
#include "framework/formats/volume/SampleBlocks.h"
#include "framework/formats/volume/StoredVolume.h"
#include "framework/formats/volume/VolumeReader.h"

namespace trephine::formats {

namespace {

struct Field {
  std::string key;
  std::string value;
};

// The header fields in file order and where the data starts in the header file.
struct MetaHeader {
  std::vector<Field> fields;
  uint64_t dataStart = 0;  // byte after the ElementDataFile line

  // The last value of the first of `keys` that is present (keys are case-insensitive).
  std::optional<std::pair<std::string, std::string>> find(std::initializer_list<const char*> keys) const {
    for (const char* key : keys) {
      for (auto it = fields.rbegin(); it != fields.rend(); ++it)
        if (equalsIgnoreCase(it->key, key)) return std::make_pair(std::string(key), it->value);
    }
    return std::nullopt;
  }
};

MetaHeader parseHeader(const ByteSource& source) {
  const std::vector<uint8_t> prefix = source.readClipped(0, kMaxHeaderBytes);
  const std::string_view text = asText(prefix);
  MetaHeader header;
  size_t position = 0;
  int lineNumber = 0;
  while (position < text.size()) {
    const HeaderLine line = headerLineAt(text, position);
    ++lineNumber;
    position = line.next;
    const std::string_view content = trim(line.text);
    if (content.empty()) continue;
    const size_t equals = content.find('=');
    if (equals == std::string_view::npos)
      throw VolumeReadError(source.path(), "line " + std::to_string(lineNumber) + ": expected 'Key = Value', found " +
                                               quoteForMessage(content));
    Field field{std::string(trim(content.substr(0, equals))), std::string(trim(content.substr(equals + 1)))};
    const bool last = equalsIgnoreCase(field.key, "ElementDataFile");
    header.fields.push_back(std::move(field));
    if (last) {
      header.dataStart = line.next;
      return header;
    }
  }
  if (source.size() > kMaxHeaderBytes)
    throw VolumeReadError(source.path(), "no ElementDataFile line in the first " + std::to_string(kMaxHeaderBytes) +
                                             " bytes (expected it to end the header)");
  throw VolumeReadError(source.path(), "no ElementDataFile line (expected it to end the header)");
}

class HeaderFields {
 public:
  HeaderFields(const MetaHeader& header, const std::filesystem::path& file) : m_header(header), m_file(file) {}

  [[noreturn]] void fail(const std::string& key, const std::string& value, const std::string& expected) const {
    throw VolumeReadError(m_file, key + " " + quoteForMessage(value) + " " + expected);
  }
  std::optional<std::vector<double>> reals(std::initializer_list<const char*> keys, size_t count) const {
    const auto field = m_header.find(keys);
    if (!field) return std::nullopt;
    auto values = parseReals(field->second, count);
    if (!values) fail(field->first, field->second, "is not " + std::to_string(count) + " numbers");
    for (double v : *values)
      if (!std::isfinite(v)) fail(field->first, field->second, "has a value that is not finite");
    return values;
  }
  std::optional<int64_t> integer(const char* key) const {
    const auto field = m_header.find({key});
    if (!field) return std::nullopt;
    const auto value = parseInteger(field->second);
    if (!value) fail(key, field->second, "is not an integer");
    return value;
  }
  std::optional<bool> boolean(std::initializer_list<const char*> keys) const {
    const auto field = m_header.find(keys);
    if (!field) return std::nullopt;
    if (equalsIgnoreCase(field->second, "True") || field->second == "1") return true;
    if (equalsIgnoreCase(field->second, "False") || field->second == "0") return false;
    fail(field->first, field->second, "is not True or False");
  }
  std::string required(const char* key) const {
    const auto field = m_header.find({key});
    if (!field) throw VolumeReadError(m_file, "no " + std::string(key) + " field");
    return field->second;
  }
  std::optional<std::string> text(const char* key) const {
    const auto field = m_header.find({key});
    return field ? std::optional(field->second) : std::nullopt;
  }

 private:
  const MetaHeader& m_header;
  const std::filesystem::path& m_file;
};

NumberType elementType(const std::string& name, const HeaderFields& fields) {
  static const std::pair<const char*, NumberType> kTypes[] = {
      {"MET_CHAR", NumberType::kInt8},     {"MET_UCHAR", NumberType::kUInt8},   {"MET_SHORT", NumberType::kInt16},
      {"MET_USHORT", NumberType::kUInt16}, {"MET_INT", NumberType::kInt32},     {"MET_UINT", NumberType::kUInt32},
      {"MET_FLOAT", NumberType::kFloat32}, {"MET_DOUBLE", NumberType::kFloat64}};
  for (const auto& [spelling, type] : kTypes)
    if (equalsIgnoreCase(name, spelling)) return type;
  fields.fail("ElementType", name,
              "is not supported (expected MET_CHAR, MET_UCHAR, MET_SHORT, MET_USHORT, MET_INT, MET_UINT, MET_FLOAT "
              "or MET_DOUBLE)");
}

std::string three(const Vec3& v) { return formatDouble(v.x()) + " " + formatDouble(v.y()) + " " + formatDouble(v.z()); }

bool isFileSeries(std::string_view value) {
  const std::vector<std::string_view> words = splitWhitespace(value);
  return words.size() >= 4 && words[0].find('%') != std::string_view::npos && parseInteger(words[1]) &&
         parseInteger(words[2]) && parseInteger(words[3]);
}

}  // namespace

bool looksLikeMetaImage(std::span<const uint8_t> head) {
  const std::string_view text = asText(head);
  size_t position = 0;
  while (position < text.size()) {
    const HeaderLine line = headerLineAt(text, position);
    position = line.next;
    const std::string_view content = trim(line.text);
    const size_t equals = content.find('=');
    if (equals == std::string_view::npos) {
      if (content.empty()) continue;
      return false;  // not a key-value header
    }
    const std::string_view key = trim(content.substr(0, equals));
    if (equalsIgnoreCase(key, "ObjectType") || equalsIgnoreCase(key, "NDims")) return true;
  }
  return false;
}

DensityVolume readMetaImage(const ByteSource& source) {
  const std::filesystem::path& file = source.path();
  const MetaHeader header = parseHeader(source);
  const HeaderFields fields(header, file);

  if (const auto objectType = fields.text("ObjectType"); objectType && !equalsIgnoreCase(*objectType, "Image"))
    fields.fail("ObjectType", *objectType, "is not supported (expected Image)");
  const auto nDims = fields.integer("NDims");
  if (!nDims) throw VolumeReadError(file, "no NDims field (expected NDims = 3)");
  if (*nDims != 3)
    throw VolumeReadError(file, "NDims " + std::to_string(*nDims) + " is not supported (expected 3: only 3D volumes)");
  if (const auto channels = fields.integer("ElementNumberOfChannels"); channels && *channels != 1)
    throw VolumeReadError(file, "ElementNumberOfChannels " + std::to_string(*channels) +
                                    " is not supported (expected 1: scalar volumes only)");
  if (const auto binary = fields.boolean({"BinaryData"}); binary && !*binary)
    throw VolumeReadError(file, "BinaryData = False (ASCII samples) is not supported (expected True)");

  StoredVolume stored;
  const std::string dimSize = fields.required("DimSize");
  const auto dims = parseIntegers(dimSize, 3);
  if (!dims) fields.fail("DimSize", dimSize, "is not 3 integers");
  stored.dims = {(*dims)[0], (*dims)[1], (*dims)[2]};
  checkDimensions(stored.dims, "DimSize", file);

  stored.layout.type = elementType(fields.required("ElementType"), fields);
  stored.layout.bigEndian = fields.boolean({"ElementByteOrderMSB", "BinaryDataByteOrderMSB"})
                                .value_or(std::endian::native == std::endian::big);

  // Spacing: ElementSpacing (centre to centre); ElementSize (voxel extent) when there is no spacing.
  Vec3 spacing = Vec3::Ones();
  if (const auto values = fields.reals({"ElementSpacing", "ElementSize"}, 3)) {
    spacing = Vec3((*values).data());
    if (spacing.cwiseAbs().minCoeff() == 0)
      throw VolumeReadError(file, "ElementSpacing " + three(spacing) + " must be non-zero (voxel size in mm)");
  }
  if (const auto values = fields.reals({"Offset", "Origin", "Position"}, 3)) stored.origin = Vec3((*values).data());
  Eigen::Matrix3d direction = Eigen::Matrix3d::Identity();
  if (const auto values = fields.reals({"TransformMatrix", "Rotation", "Orientation"}, 9)) {
    // Listed axis by axis: the first three numbers are the direction of axis 0 (ITK convention).
    for (int a = 0; a < 3; ++a) direction.col(a) = Vec3(&(*values)[3 * a]);
  }
  for (int a = 0; a < 3; ++a) {
    const double length = direction.col(a).norm();
    if (length > 0) direction.col(a) /= length;
    stored.axes.col(a) = direction.col(a) * spacing[a];
  }

  const std::string dataFile = fields.required("ElementDataFile");
  const bool compressed = fields.boolean({"CompressedData"}).value_or(false);
  std::optional<uint64_t> compressedSize;
  if (const auto size = fields.integer("CompressedDataSize")) {
    if (*size < 0) throw VolumeReadError(file, "CompressedDataSize " + std::to_string(*size) + " is negative");
    if (*size > 0) compressedSize = uint64_t(*size);
  }
  const int64_t headerSize = fields.integer("HeaderSize").value_or(0);
  if (headerSize < -1)
    throw VolumeReadError(file, "HeaderSize " + std::to_string(headerSize) + " is not supported (expected -1 or more)");

  std::unique_ptr<FileByteSource> detached;
  const ByteSource* data = &source;
  uint64_t offset = header.dataStart;
  if (equalsIgnoreCase(dataFile, "LIST") || dataFile.rfind("LIST ", 0) == 0) {
    throw VolumeReadError(file,
                          "ElementDataFile = LIST (one file per slice) is not supported (expected LOCAL or "
                          "one data file name; join the slices into one .mha first)");
  } else if (isFileSeries(dataFile)) {
    fields.fail("ElementDataFile", dataFile,
                "(a numbered file series) is not supported (expected LOCAL or one data file name)");
  } else if (!equalsIgnoreCase(dataFile, "LOCAL")) {
    if (!isPlainFileName(dataFile))
      fields.fail("ElementDataFile", dataFile, "is not a file name (expected LOCAL or a data file name)");
    detached = std::make_unique<FileByteSource>(file.parent_path() / dataFile);
    data = detached.get();
    offset = 0;
  }
  // HeaderSize: bytes to skip in the data file (-1: the samples are the last bytes of the file).
  BlockStart start{headerSize > 0 ? uint64_t(headerSize) : offset, headerSize == -1, 0};

  std::vector<uint8_t> samples;
  if (!compressed) {
    appendRawSamples(*data, start, stored.byteCount(), samples);
  } else {
    uint64_t streamOffset = start.offset;
    if (start.fromEnd) {
      if (!compressedSize)
        throw VolumeReadError(file, "HeaderSize = -1 with CompressedData = True needs CompressedDataSize");
      if (*compressedSize > data->size())
        throw VolumeReadError(data->path(), "truncated: expected " + std::to_string(*compressedSize) +
                                                " bytes of compressed data, found " + std::to_string(data->size()));
      streamOffset = data->size() - *compressedSize;
    }
    appendCompressedSamples(*data, streamOffset, compressedSize, BlockStart{}, stored.byteCount(), samples);
  }
  return assembleVolume(stored, samples, file);
}

}  // namespace trephine::formats
