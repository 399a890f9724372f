#pragma once
// The numeric types files store samples and arrays in: volume samples
// (MetaImage, NRRD, NIfTI and DICOM name them their own ways; their readers
// map the names), VTK arrays by their names in legacy files ("float", "int",
// "vtktypeint64") and XML files ("Float32", "Int64"), and decoding packed
// binary values of such a type in either byte order.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace trephine::formats {

enum class NumberType { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kInt64, kUInt64, kFloat32, kFloat64 };

size_t byteSize(NumberType type);
bool isInteger(NumberType type);
// "int16", "float32", ... for messages.
std::string numberTypeName(NumberType type);

// XML names: Int8 ... UInt64, Float32, Float64.
std::optional<NumberType> xmlNumberType(std::string_view name);
// Legacy names (case-insensitive): char, unsigned_char, short, ..., long
// (8 bytes, as VTK writes it on 64-bit systems), float, double, vtktypeint64, vtkidtype, ...
std::optional<NumberType> legacyNumberType(std::string_view name);

// Appends the values packed in `bytes` (a whole number of values) to `out`.
void decodeNumbers(std::string_view bytes, NumberType type, bool bigEndian, std::vector<double>& out);
// Integers only (the caller checked isInteger): unsigned 64-bit values above
// INT64_MAX saturate, and are then refused as out of range by the caller.
void decodeNumbers(std::string_view bytes, NumberType type, bool bigEndian, std::vector<int64_t>& out);

}  // namespace trephine::formats
