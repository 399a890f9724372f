#include "framework/formats/volume/NrrdReader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "framework/core/Strings.h"
#include "framework/formats/volume/HeaderText.h"
#include "framework/formats/volume/NrrdDataFiles.h"
#include "framework/formats/volume/SampleBlocks.h"
#include "framework/formats/volume/StoredVolume.h"
#include "framework/formats/volume/VolumeReader.h"

namespace trephine::formats {

namespace {

struct NrrdHeader {
  std::map<std::string, std::string> fields;  // canonical field name -> value
  std::vector<std::string> listedFiles;       // names after "data file: LIST"
  std::optional<uint64_t> dataStart;          // byte after the blank line ending the header
};

// Canonical names of the fields that have alternative spellings.
std::string canonicalField(std::string_view name) {
  const std::string lower = toLower(name);
  if (lower == "datafile") return "data file";
  if (lower == "lineskip") return "line skip";
  if (lower == "byteskip") return "byte skip";
  if (lower == "axismins") return "axis mins";
  if (lower == "centerings") return "centers";
  return lower;
}

bool isListValue(std::string_view value) {
  const std::vector<std::string_view> words = splitWhitespace(value);
  return !words.empty() && words.size() <= 2 && words[0] == "LIST";
}

NrrdHeader parseHeader(const ByteSource& source) {
  const std::vector<uint8_t> prefix = source.readClipped(0, kMaxHeaderBytes);
  const std::string_view text = asText(prefix);
  const HeaderLine magic = headerLineAt(text, 0);
  const std::string_view version = magic.text.substr(0, std::min<size_t>(magic.text.size(), 9));
  const bool known = (magic.text.size() == 8 && magic.text.substr(0, 7) == "NRRD000" && magic.text[7] >= '1' &&
                      magic.text[7] <= '5') ||
                     magic.text == "NRRD00.01";
  if (!known) {
    if (magic.text.substr(0, 4) == "NRRD")
      throw VolumeReadError(source.path(), "NRRD version " + quoteForMessage(magic.text) +
                                               " is not supported (expected NRRD0001 to NRRD0005)");
    throw VolumeReadError(source.path(), "not a NRRD file: it starts with " + quoteForMessage(version) +
                                             " (expected the magic NRRD0001 to NRRD0005)");
  }
  NrrdHeader header;
  bool listing = false;
  size_t position = magic.next;
  int lineNumber = 1;
  while (position < text.size()) {
    const HeaderLine line = headerLineAt(text, position);
    ++lineNumber;
    position = line.next;
    if (line.text.empty()) {
      if (line.terminated) header.dataStart = line.next;
      return header;
    }
    if (line.text.front() == '#') continue;
    if (listing) {
      header.listedFiles.emplace_back(trim(line.text));
      continue;
    }
    const size_t colon = line.text.find(':');
    if (colon == std::string_view::npos)
      throw VolumeReadError(source.path(), "line " + std::to_string(lineNumber) + ": expected 'field: value', found " +
                                               quoteForMessage(line.text));
    if (colon + 1 < line.text.size() && line.text[colon + 1] == '=') continue;  // key:=value pairs carry no geometry
    const std::string name = canonicalField(trim(line.text.substr(0, colon)));
    const std::string value(trim(line.text.substr(colon + 1)));
    if (!header.fields.emplace(name, value).second)
      throw VolumeReadError(source.path(),
                            "line " + std::to_string(lineNumber) + ": field '" + name + "' is given twice");
    listing = name == "data file" && isListValue(value);
  }
  if (source.size() > kMaxHeaderBytes)
    throw VolumeReadError(source.path(),
                          "no blank line ends the header in the first " + std::to_string(kMaxHeaderBytes) + " bytes");
  return header;  // a detached header may end with the file
}

class Fields {
 public:
  Fields(const NrrdHeader& header, const std::filesystem::path& file) : m_header(header), m_file(file) {}
  std::optional<std::string> find(const std::string& name) const {
    const auto it = m_header.fields.find(name);
    return it == m_header.fields.end() ? std::nullopt : std::optional(it->second);
  }
  std::string required(const std::string& name, const std::string& example) const {
    const auto value = find(name);
    if (!value)
      throw VolumeReadError(m_file, "no '" + name + ":' field (expected e.g. '" + name + ": " + example + "')");
    return *value;
  }
  [[noreturn]] void fail(const std::string& name, std::string_view value, const std::string& problem) const {
    throw VolumeReadError(m_file, name + " " + quoteForMessage(value) + " " + problem);
  }
  std::optional<int64_t> integer(const std::string& name) const {
    const auto value = find(name);
    if (!value) return std::nullopt;
    const auto number = parseInteger(*value);
    if (!number) fail(name, *value, "is not an integer");
    return number;
  }

 private:
  const NrrdHeader& m_header;
  const std::filesystem::path& m_file;
};

NumberType sampleType(const std::string& value, const Fields& fields) {
  // All NRRD spellings, compared with single spaces and in lower case.
  std::string spelled;
  for (std::string_view word : splitWhitespace(value)) {
    if (!spelled.empty()) spelled += ' ';
    spelled += toLower(word);
  }
  // clang-format off
  static const std::map<std::string, NumberType> kTypes = {
      {"signed char", NumberType::kInt8}, {"int8", NumberType::kInt8}, {"int8_t", NumberType::kInt8},
      {"uchar", NumberType::kUInt8}, {"unsigned char", NumberType::kUInt8}, {"uint8", NumberType::kUInt8},
      {"uint8_t", NumberType::kUInt8},
      {"short", NumberType::kInt16}, {"short int", NumberType::kInt16}, {"signed short", NumberType::kInt16},
      {"signed short int", NumberType::kInt16}, {"int16", NumberType::kInt16}, {"int16_t", NumberType::kInt16},
      {"ushort", NumberType::kUInt16}, {"unsigned short", NumberType::kUInt16},
      {"unsigned short int", NumberType::kUInt16}, {"uint16", NumberType::kUInt16}, {"uint16_t", NumberType::kUInt16},
      {"int", NumberType::kInt32}, {"signed int", NumberType::kInt32}, {"int32", NumberType::kInt32},
      {"int32_t", NumberType::kInt32},
      {"uint", NumberType::kUInt32}, {"unsigned int", NumberType::kUInt32}, {"uint32", NumberType::kUInt32},
      {"uint32_t", NumberType::kUInt32},
      {"float", NumberType::kFloat32}, {"double", NumberType::kFloat64}};
  // clang-format on
  const auto it = kTypes.find(spelled);
  if (it == kTypes.end())
    fields.fail("type", value,
                "is not supported (expected signed or unsigned char, short, int (8, 16 or 32 bits), float or "
                "double)");
  return it->second;
}

// "(x,y,z)" vectors separated by spaces; "none" for non-spatial axes (refused here).
std::vector<Vec3> parseVectors(const std::string& name, const std::string& value, size_t count, const Fields& fields) {
  std::vector<Vec3> vectors;
  size_t n = 0;
  while (true) {
    while (n < value.size() && std::isspace(static_cast<unsigned char>(value[n]))) ++n;
    if (n >= value.size()) break;
    if (value.compare(n, 4, "none") == 0) fields.fail(name, value, "has 'none' for an axis (expected 3 spatial axes)");
    if (value[n] != '(') fields.fail(name, value, "is not a list of '(x,y,z)' vectors");
    const size_t close = value.find(')', n);
    if (close == std::string::npos) fields.fail(name, value, "has a '(' without ')'");
    const std::string_view inner = std::string_view(value).substr(n + 1, close - n - 1);
    std::vector<double> components;
    size_t start = 0;
    while (true) {
      const size_t comma = inner.find(',', start);
      const auto component =
          parseReal(trim(inner.substr(start, comma == std::string_view::npos ? inner.npos : comma - start)));
      if (!component || !std::isfinite(*component))
        fields.fail(name, value, "has a component that is not a finite number");
      components.push_back(*component);
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    if (components.size() != 3)
      fields.fail(name, value,
                  "has a vector of " + std::to_string(components.size()) +
                      " components (expected 3: only 3D spaces are supported)");
    vectors.emplace_back(components[0], components[1], components[2]);
    n = close + 1;
  }
  if (vectors.size() != count)
    fields.fail(name, value,
                "has " + std::to_string(vectors.size()) + " vectors (expected " + std::to_string(count) + ")");
  return vectors;
}

// The patient frame of the "space" field (none without one).
PatientFrame checkSpace(const Fields& fields) {
  const auto space = fields.find("space");
  if (!space) return PatientFrame::kNone;
  // clang-format off
  static const char* const kSpaces[] = {
      "right-anterior-superior", "ras", "left-anterior-superior", "las", "left-posterior-superior", "lps",
      "scanner-xyz", "3d-right-handed", "3d-left-handed"};
  // clang-format on
  const std::string lower = toLower(*space);
  for (const char* known : kSpaces)
    if (lower == known) {
      if (lower == "right-anterior-superior" || lower == "ras") return PatientFrame::kRas;
      if (lower == "left-anterior-superior" || lower == "las") return PatientFrame::kLas;
      if (lower == "left-posterior-superior" || lower == "lps") return PatientFrame::kLps;
      return PatientFrame::kNone;
    }
  fields.fail("space", *space,
              "is not supported (expected a 3D space: RAS, LAS, LPS, scanner-xyz, 3D-right-handed or 3D-left-handed)");
  return PatientFrame::kNone;
}

// Fills stored.axes and stored.origin from space directions / spacings, space origin / axis mins.
void readGeometry(const Fields& fields, StoredVolume& stored) {
  const PatientFrame frame = checkSpace(fields);
  const auto directions = fields.find("space directions");
  const auto spacings = fields.find("spacings");
  if (directions) {
    // Each vector is the step between samples along one axis (direction times spacing).
    const std::vector<Vec3> vectors = parseVectors("space directions", *directions, 3, fields);
    for (int a = 0; a < 3; ++a) stored.axes.col(a) = vectors[a];
  } else if (spacings) {
    // Spacings without directions (allowed without "space"; some files, e.g. VTK's headsq, give both):
    // the axes are the world axes.
    const auto values = parseReals(*spacings, 3);
    if (!values) fields.fail("spacings", *spacings, "is not 3 numbers");
    for (double s : *values)
      if (!std::isfinite(s) || s == 0) fields.fail("spacings", *spacings, "must be 3 finite, non-zero numbers");
    stored.axes = Vec3((*values).data()).asDiagonal();
  }
  if (const auto origin = fields.find("space origin")) {
    stored.origin = parseVectors("space origin", *origin, 1, fields)[0];
  } else if (const auto mins = fields.find("axis mins"); mins && !directions) {
    // Without a space, the first sample sits at the axis minimum (node centring) or half a sample above it (cell).
    const auto values = parseReals(*mins, 3);
    if (!values) fields.fail("axis mins", *mins, "is not 3 numbers");
    std::vector<std::string_view> centers;
    const auto centersValue = fields.find("centers");
    if (centersValue) centers = splitWhitespace(*centersValue);
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite((*values)[a])) continue;
      const bool node = a < int(centers.size()) && centers[a] == "node";
      stored.origin[a] = (*values)[a] + (node ? 0.0 : 0.5 * stored.axes(a, a));
    }
  }
  convertToLps(stored, frame);  // the scene's world is LPS
}

}  // namespace

bool looksLikeNrrd(std::span<const uint8_t> head) { return head.size() >= 4 && asText(head).substr(0, 4) == "NRRD"; }

DensityVolume readNrrd(const ByteSource& source) {
  const std::filesystem::path& file = source.path();
  const NrrdHeader header = parseHeader(source);
  const Fields fields(header, file);

  const std::string dimensionText = fields.required("dimension", "3");
  const auto dimension = parseInteger(dimensionText);
  if (!dimension) fields.fail("dimension", dimensionText, "is not an integer");
  if (*dimension != 3)
    throw VolumeReadError(
        file, "dimension " + std::to_string(*dimension) + " is not supported (expected 3: only 3D volumes)");
  if (const auto spaceDimension = fields.integer("space dimension"); spaceDimension && *spaceDimension != 3)
    throw VolumeReadError(file,
                          "space dimension " + std::to_string(*spaceDimension) + " is not supported (expected 3)");

  StoredVolume stored;
  const std::string sizesText = fields.required("sizes", "256 256 128");
  const auto sizes = parseIntegers(sizesText, 3);
  if (!sizes) fields.fail("sizes", sizesText, "is not 3 integers");
  stored.dims = {(*sizes)[0], (*sizes)[1], (*sizes)[2]};
  checkDimensions(stored.dims, "sizes", file);
  stored.layout.type = sampleType(fields.required("type", "short"), fields);

  const std::string encoding = fields.required("encoding", "raw");
  const bool gzip = equalsIgnoreCase(encoding, "gzip") || equalsIgnoreCase(encoding, "gz");
  if (!gzip && !equalsIgnoreCase(encoding, "raw"))
    fields.fail("encoding", encoding, "is not supported (expected raw or gzip)");
  if (const auto endian = fields.find("endian")) {
    if (equalsIgnoreCase(*endian, "big"))
      stored.layout.bigEndian = true;
    else if (!equalsIgnoreCase(*endian, "little"))
      fields.fail("endian", *endian, "is not little or big");
  } else if (byteSize(stored.layout.type) > 1) {
    throw VolumeReadError(file, "no 'endian:' field (expected 'endian: little' or 'endian: big' for " +
                                    numberTypeName(stored.layout.type) + " samples)");
  }
  readGeometry(fields, stored);

  const int64_t lineSkip = fields.integer("line skip").value_or(0);
  if (lineSkip < 0) throw VolumeReadError(file, "line skip " + std::to_string(lineSkip) + " is negative");
  const int64_t byteSkip = fields.integer("byte skip").value_or(0);
  // Byte skip -1 - n: the samples are followed by n bytes (teem's extension of -1: "the last bytes").
  const BlockStart start{byteSkip > 0 ? uint64_t(byteSkip) : 0, byteSkip < 0,
                         byteSkip < 0 ? uint64_t(-(byteSkip + 1)) : 0};

  // The sources of the samples: the header file itself, or the data files.
  std::vector<std::filesystem::path> dataFiles;
  std::optional<int64_t> slabDimension;
  if (const auto dataFile = fields.find("data file")) {
    if (isListValue(*dataFile)) {
      const std::vector<std::string_view> words = splitWhitespace(*dataFile);
      if (words.size() == 2) {
        slabDimension = parseInteger(words[1]);
        if (!slabDimension) fields.fail("data file", *dataFile, "has a slab dimension that is not an integer");
      }
      for (const std::string& name : header.listedFiles) {
        if (!isPlainFileName(name))
          throw VolumeReadError(file, "data file list entry " + quoteForMessage(name) + " is not a file name");
        dataFiles.push_back(file.parent_path() / name);
      }
      if (dataFiles.empty()) throw VolumeReadError(file, "data file: LIST is followed by no file names");
    } else {
      const NrrdDataFiles expanded = expandNrrdDataFile(*dataFile, file, stored.voxelCount());
      dataFiles = expanded.files;
      slabDimension = expanded.slabDimension;
    }
  } else if (!header.dataStart) {
    throw VolumeReadError(file, "no data: expected a blank line followed by the samples, or a 'data file:' field");
  }

  const uint64_t fileCount = dataFiles.empty() ? 1 : dataFiles.size();
  const uint64_t voxels = stored.voxelCount();
  if (slabDimension && (*slabDimension < 1 || *slabDimension > 3))
    throw VolumeReadError(file, "data file slab dimension " + std::to_string(*slabDimension) + " is not 1, 2 or 3");
  // Each file holds the same share of the samples: one slab of the first
  // (slab dimension) axes per file, by default one slice.
  const int64_t slab = slabDimension.value_or(dataFiles.size() > 1 ? 2 : 3);
  uint64_t slabVoxels = 1;
  for (int64_t a = 0; a < slab; ++a) slabVoxels *= uint64_t(stored.dims[a]);
  if (slab < 3 && voxels / slabVoxels != fileCount)
    throw VolumeReadError(file, "data file names " + std::to_string(fileCount) + " files but sizes " + sizesText +
                                    " needs " + std::to_string(voxels / slabVoxels) + " (one per slab of dimension " +
                                    std::to_string(slab) + ")");
  if (voxels % fileCount != 0)
    throw VolumeReadError(file, "data file names " + std::to_string(fileCount) + " files, which do not share the " +
                                    std::to_string(voxels) + " samples of sizes " + sizesText + " evenly");
  const uint64_t bytesPerFile = voxels / fileCount * byteSize(stored.layout.type);

  std::vector<uint8_t> samples;
  const auto readBlock = [&](const ByteSource& data, uint64_t headerEnd) {
    const uint64_t offset = skipLines(data, headerEnd, lineSkip);
    if (gzip) {
      appendCompressedSamples(data, offset, std::nullopt, start, bytesPerFile, samples);
    } else {
      BlockStart raw = start;
      raw.offset += offset;
      appendRawSamples(data, raw, bytesPerFile, samples);
    }
  };
  if (dataFiles.empty()) {
    readBlock(source, *header.dataStart);
  } else {
    for (const std::filesystem::path& dataFile : dataFiles) readBlock(FileByteSource(dataFile), 0);
  }
  return assembleVolume(stored, samples, file);
}

}  // namespace trephine::formats
