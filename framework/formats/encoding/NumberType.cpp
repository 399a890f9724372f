#include "framework/formats/encoding/NumberType.h"

#include <bit>
#include <cstring>
#include <limits>
#include <type_traits>

#include "framework/formats/encoding/TextTokens.h"

namespace trephine::formats {

namespace {

template <typename T>
T load(const char* bytes, bool bigEndian) {
  using Bits = std::conditional_t<
      sizeof(T) == 1, uint8_t,
      std::conditional_t<sizeof(T) == 2, uint16_t, std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>>;
  Bits bits = 0;
  for (size_t b = 0; b < sizeof(T); ++b) {
    const size_t shift = 8 * (bigEndian ? sizeof(T) - 1 - b : b);
    bits |= Bits(Bits(uint8_t(bytes[b])) << shift);
  }
  return std::bit_cast<T>(bits);
}

template <typename T, typename Out>
void decodeAs(std::string_view bytes, bool bigEndian, std::vector<Out>& out) {
  const size_t count = bytes.size() / sizeof(T);
  out.reserve(out.size() + count);
  for (size_t i = 0; i < count; ++i) {
    const T value = load<T>(bytes.data() + i * sizeof(T), bigEndian);
    if constexpr (std::is_same_v<T, uint64_t> && std::is_same_v<Out, int64_t>) {
      out.push_back(value > uint64_t(std::numeric_limits<int64_t>::max()) ? std::numeric_limits<int64_t>::max()
                                                                          : int64_t(value));
    } else {
      out.push_back(static_cast<Out>(value));
    }
  }
}

template <typename Out>
void decode(std::string_view bytes, NumberType type, bool bigEndian, std::vector<Out>& out) {
  switch (type) {
    case NumberType::kInt8:
      return decodeAs<int8_t>(bytes, bigEndian, out);
    case NumberType::kUInt8:
      return decodeAs<uint8_t>(bytes, bigEndian, out);
    case NumberType::kInt16:
      return decodeAs<int16_t>(bytes, bigEndian, out);
    case NumberType::kUInt16:
      return decodeAs<uint16_t>(bytes, bigEndian, out);
    case NumberType::kInt32:
      return decodeAs<int32_t>(bytes, bigEndian, out);
    case NumberType::kUInt32:
      return decodeAs<uint32_t>(bytes, bigEndian, out);
    case NumberType::kInt64:
      return decodeAs<int64_t>(bytes, bigEndian, out);
    case NumberType::kUInt64:
      return decodeAs<uint64_t>(bytes, bigEndian, out);
    case NumberType::kFloat32:
      if constexpr (std::is_same_v<Out, double>) return decodeAs<float>(bytes, bigEndian, out);
      break;
    case NumberType::kFloat64:
      if constexpr (std::is_same_v<Out, double>) return decodeAs<double>(bytes, bigEndian, out);
      break;
  }
}

}  // namespace

size_t byteSize(NumberType type) {
  switch (type) {
    case NumberType::kInt8:
    case NumberType::kUInt8:
      return 1;
    case NumberType::kInt16:
    case NumberType::kUInt16:
      return 2;
    case NumberType::kInt32:
    case NumberType::kUInt32:
    case NumberType::kFloat32:
      return 4;
    case NumberType::kInt64:
    case NumberType::kUInt64:
    case NumberType::kFloat64:
      return 8;
  }
  return 1;
}

bool isInteger(NumberType type) { return type != NumberType::kFloat32 && type != NumberType::kFloat64; }

std::string numberTypeName(NumberType type) {
  switch (type) {
    case NumberType::kInt8:
      return "int8";
    case NumberType::kUInt8:
      return "uint8";
    case NumberType::kInt16:
      return "int16";
    case NumberType::kUInt16:
      return "uint16";
    case NumberType::kInt32:
      return "int32";
    case NumberType::kUInt32:
      return "uint32";
    case NumberType::kInt64:
      return "int64";
    case NumberType::kUInt64:
      return "uint64";
    case NumberType::kFloat32:
      return "float32";
    case NumberType::kFloat64:
      return "float64";
  }
  return "unknown";
}

std::optional<NumberType> xmlNumberType(std::string_view name) {
  static constexpr std::pair<std::string_view, NumberType> kNames[] = {
      {"Int8", NumberType::kInt8},      {"UInt8", NumberType::kUInt8},   {"Int16", NumberType::kInt16},
      {"UInt16", NumberType::kUInt16},  {"Int32", NumberType::kInt32},   {"UInt32", NumberType::kUInt32},
      {"Int64", NumberType::kInt64},    {"UInt64", NumberType::kUInt64}, {"Float32", NumberType::kFloat32},
      {"Float64", NumberType::kFloat64}};
  for (const auto& [known, type] : kNames)
    if (name == known) return type;
  return std::nullopt;
}

std::optional<NumberType> legacyNumberType(std::string_view name) {
  static constexpr std::pair<std::string_view, NumberType> kNames[] = {{"char", NumberType::kInt8},
                                                                       {"signed_char", NumberType::kInt8},
                                                                       {"unsigned_char", NumberType::kUInt8},
                                                                       {"short", NumberType::kInt16},
                                                                       {"unsigned_short", NumberType::kUInt16},
                                                                       {"int", NumberType::kInt32},
                                                                       {"unsigned_int", NumberType::kUInt32},
                                                                       {"long", NumberType::kInt64},
                                                                       {"unsigned_long", NumberType::kUInt64},
                                                                       {"vtktypeint8", NumberType::kInt8},
                                                                       {"vtktypeuint8", NumberType::kUInt8},
                                                                       {"vtktypeint16", NumberType::kInt16},
                                                                       {"vtktypeuint16", NumberType::kUInt16},
                                                                       {"vtktypeint32", NumberType::kInt32},
                                                                       {"vtktypeuint32", NumberType::kUInt32},
                                                                       {"vtktypeint64", NumberType::kInt64},
                                                                       {"vtktypeuint64", NumberType::kUInt64},
                                                                       {"vtkidtype", NumberType::kInt64},
                                                                       {"float", NumberType::kFloat32},
                                                                       {"double", NumberType::kFloat64}};
  for (const auto& [known, type] : kNames)
    if (equalsIgnoreCase(name, known)) return type;
  return std::nullopt;
}

void decodeNumbers(std::string_view bytes, NumberType type, bool bigEndian, std::vector<double>& out) {
  decode(bytes, type, bigEndian, out);
}

void decodeNumbers(std::string_view bytes, NumberType type, bool bigEndian, std::vector<int64_t>& out) {
  decode(bytes, type, bigEndian, out);
}

}  // namespace trephine::formats
