#pragma once
// The values of one VTK XML <DataArray>: ascii text, or binary (a
// byte-count header and the packed values, or a block header and
// zlib-compressed blocks), either inline as base64 or in the file's
// <AppendedData> at the array's offset, raw or base64. The array is
// described by plain strings so that the XML parser stays inside
// VtkXmlFile.cpp.
#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

namespace trephine::formats {

// How the file encodes binary arrays (attributes of <VTKFile>).
struct VtkXmlEncoding {
  bool bigEndian = false;  // byte_order="BigEndian"
  bool header64 = false;   // header_type="UInt64" (default UInt32)
  bool zlib = false;       // compressor="vtkZLibDataCompressor"
  // <AppendedData>: its content after the '_' marker (offsets count from
  // there), raw bytes or base64 text (encoding="base64").
  bool hasAppended = false;
  bool appendedBase64 = false;
  std::string_view appended;
};

struct VtkXmlArray {
  std::string_view name;    // Name attribute, for messages
  std::string_view type;    // "Float32", "Int64", ...
  std::string_view format;  // "ascii", "binary" or "appended"
  std::string_view text;    // the element's text
  uint64_t offset = 0;      // format="appended": where its data starts in VtkXmlEncoding::appended
  size_t line = 0;          // line of the <DataArray> tag
};

// Exactly `count` values of the array, or a TetMeshReadError naming the file,
// the line and the array. Counts come from the caller (NumberOfPoints, ...)
// and are checked against the data before anything is allocated for them.
std::vector<double> readVtkXmlReals(const VtkXmlArray& array, int64_t count, const VtkXmlEncoding& encoding,
                                 const std::filesystem::path& file);
// Integer-typed arrays only (connectivity, offsets, types, labels).
std::vector<int64_t> readVtkXmlIntegers(const VtkXmlArray& array, int64_t count, const VtkXmlEncoding& encoding,
                                     const std::filesystem::path& file);

}  // namespace trephine::formats
