#include "plugins/openigtlink/IgtlMessages.h"

#include <cmath>
#include <cstring>

namespace trephine::openigtlink {
namespace {

constexpr uint64_t kPolynomial = 0x42F0E1EBA9EA3693ull;

constexpr std::array<uint64_t, 256> makeTable() {
  std::array<uint64_t, 256> table{};
  for (uint64_t i = 0; i < 256; ++i) {
    uint64_t crc = i << 56;
    for (int bit = 0; bit < 8; ++bit) crc = (crc & (1ull << 63)) ? (crc << 1) ^ kPolynomial : crc << 1;
    table[i] = crc;
  }
  return table;
}
constexpr std::array<uint64_t, 256> kTable = makeTable();

uint64_t getBig(const unsigned char* at, int bytes) {
  uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | at[i];
  return v;
}
void putBig(unsigned char* at, uint64_t v, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) {
    at[i] = static_cast<unsigned char>(v & 0xffu);
    v >>= 8;
  }
}
float getFloat32(const unsigned char* at) {
  const uint32_t bits = static_cast<uint32_t>(getBig(at, 4));
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}
void putFloat64(unsigned char* at, double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, 8);
  putBig(at, bits, 8);
}

// Printable ASCII up to the first NUL, and nothing after it but NULs.
template <size_t N>
bool readName(const unsigned char* at, std::array<char, N + 1>& out) {
  bool ended = false;
  for (size_t i = 0; i < N; ++i) {
    const unsigned char c = at[i];
    if (c == 0) {
      ended = true;
    } else if (ended || c < 0x20 || c > 0x7e) {
      return false;
    }
    out[i] = ended ? '\0' : static_cast<char>(c);
  }
  out[N] = '\0';
  return true;
}

}  // namespace

uint64_t crc64(std::span<const unsigned char> data, uint64_t crc) {
  for (const unsigned char byte : data) crc = kTable[((crc >> 56) ^ byte) & 0xffu] ^ (crc << 8);
  return crc;
}

std::optional<MessageHeader> decodeHeader(std::span<const unsigned char, kHeaderSize> b) {
  MessageHeader h;
  h.version = static_cast<uint16_t>(getBig(b.data(), 2));
  if (h.version < 1 || h.version > 3) return std::nullopt;
  if (!readName<kTypeSize>(b.data() + 2, h.type) || h.type[0] == '\0') return std::nullopt;
  if (!readName<kDeviceNameSize>(b.data() + 14, h.device)) return std::nullopt;
  h.timestamp = getBig(b.data() + 34, 8);
  h.bodySize = getBig(b.data() + 42, 8);
  h.crc = getBig(b.data() + 50, 8);
  return h;
}

void encodeHeader(const MessageHeader& h, std::span<unsigned char, kHeaderSize> out) {
  std::memset(out.data(), 0, kHeaderSize);
  putBig(out.data(), h.version, 2);
  std::memcpy(out.data() + 2, h.type.data(), std::min(std::strlen(h.type.data()), kTypeSize));
  std::memcpy(out.data() + 14, h.device.data(), std::min(std::strlen(h.device.data()), kDeviceNameSize));
  putBig(out.data() + 34, h.timestamp, 8);
  putBig(out.data() + 42, h.bodySize, 8);
  putBig(out.data() + 50, h.crc, 8);
}

std::optional<std::span<const unsigned char>> messageContent(const MessageHeader& header,
                                                            std::span<const unsigned char> body) {
  if (header.version == 1) return body;
  // Extended header: its own size (u16), the metadata's header size (u16),
  // the metadata's size (u32), a message id (u32); the metadata ends the body.
  if (body.size() < 12) return std::nullopt;
  const uint64_t extended = getBig(body.data(), 2);
  const uint64_t metadata = getBig(body.data() + 2, 2) + getBig(body.data() + 4, 4);
  if (extended < 12 || extended + metadata > body.size()) return std::nullopt;
  return body.subspan(extended, body.size() - extended - metadata);
}

std::optional<Transform> decodeTransform(std::span<const unsigned char> content) {
  if (content.size() != 48) return std::nullopt;
  double v[12];
  for (int i = 0; i < 12; ++i) {
    v[i] = getFloat32(content.data() + 4 * i);
    if (!std::isfinite(v[i])) return std::nullopt;
  }
  Transform t;
  for (int column = 0; column < 3; ++column)
    for (int row = 0; row < 3; ++row) t.rotation(row, column) = v[3 * column + row];
  t.translation = Vec3(v[9], v[10], v[11]);
  constexpr double kTolerance = 1e-2;
  const Eigen::Matrix3d gram = t.rotation.transpose() * t.rotation;
  if ((gram - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > kTolerance) return std::nullopt;
  if (std::abs(t.rotation.determinant() - 1.0) > kTolerance) return std::nullopt;
  return t;
}

std::optional<std::string_view> decodeString(std::span<const unsigned char> content) {
  if (content.size() < 4) return std::nullopt;
  const size_t length = getBig(content.data() + 2, 2);
  if (4 + length > content.size()) return std::nullopt;
  return std::string_view(reinterpret_cast<const char*>(content.data() + 4), length);
}

std::optional<int64_t> decodeStatusSubcode(std::span<const unsigned char> content) {
  if (content.size() < 2 + 8 + 20) return std::nullopt;
  return static_cast<int64_t>(getBig(content.data() + 2, 8));
}

uint64_t newtonUnit() {
  // Prefix in the top 4 bits, then six (unit: 6 bits, exponent: 4 bits) pairs.
  constexpr uint64_t kNewton = 0x0B;
  return (0ull << 60) | (kNewton << 54) | (1ull << 50);
}

void encodeForceSensor(std::string_view deviceName, uint64_t timestamp, const Vec3& force_N,
                       std::span<unsigned char, kForceSensorMessageSize> out) {
  unsigned char* body = out.data() + kHeaderSize;
  body[0] = 3;  // three values
  body[1] = 0;  // status: reserved
  putBig(body + 2, newtonUnit(), 8);
  for (int i = 0; i < 3; ++i) putFloat64(body + 10 + 8 * i, force_N[i]);
  MessageHeader h;
  h.version = 1;
  std::memcpy(h.type.data(), "SENSOR", 6);
  std::memcpy(h.device.data(), deviceName.data(), std::min(deviceName.size(), kDeviceNameSize));
  h.timestamp = timestamp;
  h.bodySize = kForceSensorBodySize;
  h.crc = crc64({body, kForceSensorBodySize});
  encodeHeader(h, out.first<kHeaderSize>());
}

uint64_t toTimestamp(double seconds) {
  if (!(seconds >= 0)) return 0;
  const double whole = std::floor(seconds);
  const double fraction = seconds - whole;
  return (static_cast<uint64_t>(whole) << 32) | static_cast<uint64_t>(fraction * 4294967296.0);
}

}  // namespace trephine::openigtlink
