#pragma once
// The OpenIGTLink messages a device server reads and writes, by hand and
// allocation-free: the 58-byte header (version 1, and versions 2 and 3 with
// their extended header and metadata), CRC-64 (ECMA-182, as the protocol's
// reference library computes it), and the bodies of TRANSFORM (in), STRING
// and STATUS (buttons, in) and SENSOR (the force, out). Big-endian, as the
// protocol says. The exporter's larger messages (IMAGE, POLYDATA) are packed
// by Debian's libopenigtlink instead.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "framework/math/Math.h"

namespace trephine::openigtlink {

inline constexpr size_t kHeaderSize = 58;
inline constexpr size_t kTypeSize = 12;
inline constexpr size_t kDeviceNameSize = 20;

struct MessageHeader {
  uint16_t version = 1;
  std::array<char, kTypeSize + 1> type{};          // NUL-terminated
  std::array<char, kDeviceNameSize + 1> device{};  // NUL-terminated
  uint64_t timestamp = 0;  // seconds in the high 32 bits, a binary fraction in the low
  uint64_t bodySize = 0;
  uint64_t crc = 0;

  std::string_view typeName() const { return type.data(); }
  std::string_view deviceName() const { return device.data(); }
};

// CRC-64 (ECMA-182 polynomial, initial value 0, no reflection), continued from `crc`.
uint64_t crc64(std::span<const unsigned char> data, uint64_t crc = 0);

// Reads a header; nullopt for one no client of this protocol sends (a
// version other than 1 to 3, a type name with bytes that are not printable
// ASCII, or empty).
std::optional<MessageHeader> decodeHeader(std::span<const unsigned char, kHeaderSize> bytes);
void encodeHeader(const MessageHeader& header, std::span<unsigned char, kHeaderSize> out);

// A body's content: the whole body in version 1; in versions 2 and 3, what
// lies between the extended header and the metadata. nullopt when the
// extended header does not fit the body.
std::optional<std::span<const unsigned char>> messageContent(const MessageHeader& header,
                                                            std::span<const unsigned char> body);

// TRANSFORM: a rotation (its columns) and a translation (mm), float32. nullopt
// when the content is not 48 bytes, a value is not finite, or the rotation is
// not one (columns of unit length and square to each other within 1e-2, a
// determinant of +1): a tracker's matrix in single precision is within that.
struct Transform {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Vec3 translation = Vec3::Zero();  // mm
};
std::optional<Transform> decodeTransform(std::span<const unsigned char> content);

// STRING (encoding u16, length u16, the bytes): the text, when it fits.
std::optional<std::string_view> decodeString(std::span<const unsigned char> content);
// STATUS (code u16, subcode i64, error name char[20], message): the subcode.
std::optional<int64_t> decodeStatusSubcode(std::span<const unsigned char> content);

// SENSOR with three float64 values in newtons: header and body, in one buffer.
inline constexpr size_t kForceSensorBodySize = 1 + 1 + 8 + 3 * 8;
inline constexpr size_t kForceSensorMessageSize = kHeaderSize + kForceSensorBodySize;
// The unit field of a SENSOR in newtons (no prefix, newton to the power 1).
uint64_t newtonUnit();
void encodeForceSensor(std::string_view deviceName, uint64_t timestamp, const Vec3& force_N,
                       std::span<unsigned char, kForceSensorMessageSize> out);

// A time (s since the epoch) as the protocol's timestamp.
uint64_t toTimestamp(double seconds);

}  // namespace trephine::openigtlink
