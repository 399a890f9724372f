// The device server's hand-written OpenIGTLink messages against Debian's
// libopenigtlink, an independent implementation: the same CRC-64, a TRANSFORM
// the library packs read back to its matrix, a SENSOR written here unpacked
// by the library (its CRC, its three values, its unit: newtons), a version 2
// message's content found inside its extended header and metadata, and a
// stream cut anywhere read the same.
#include <gtest/gtest.h>

#include <igtlSensorMessage.h>
#include <igtlTransformMessage.h>
#include <igtl_unit.h>
#include <igtl_util.h>

#include <cstring>
#include <random>
#include <vector>

#include "plugins/openigtlink/IgtlMessages.h"
#include "plugins/openigtlink/IgtlStreamReader.h"

namespace trephine::openigtlink {
namespace {

std::vector<unsigned char> packed(igtl::MessageBase* message) {
  message->Pack();
  const auto* bytes = static_cast<const unsigned char*>(message->GetPackPointer());
  return std::vector<unsigned char>(bytes, bytes + message->GetPackSize());
}

igtl::TransformMessage::Pointer libraryTransform(double angle, float tx, float ty, float tz) {
  auto message = igtl::TransformMessage::New();
  message->SetDeviceName("Tool");
  igtl::Matrix4x4 m;
  igtl::IdentityMatrix(m);
  m[0][0] = static_cast<float>(std::cos(angle));
  m[0][1] = static_cast<float>(-std::sin(angle));
  m[1][0] = static_cast<float>(std::sin(angle));
  m[1][1] = static_cast<float>(std::cos(angle));
  m[0][3] = tx;
  m[1][3] = ty;
  m[2][3] = tz;
  message->SetMatrix(m);
  return message;
}

TEST(IgtlMessagesTest, TheCrcIsTheLibrarysOnRandomBytes) {
  std::mt19937 random(7);
  for (size_t size : {0u, 1u, 7u, 48u, 58u, 1000u, 65537u}) {
    std::vector<unsigned char> bytes(size);
    for (auto& b : bytes) b = static_cast<unsigned char>(random());
    EXPECT_EQ(openigtlink::crc64(bytes), ::crc64(bytes.data(), bytes.size(), 0ull)) << size << " bytes";
  }
}

TEST(IgtlMessagesTest, ATransformTheLibraryPacksReadsBackToItsMatrix) {
  const auto message = libraryTransform(0.3, 12.5f, -4.0f, 80.25f);
  const std::vector<unsigned char> bytes = packed(message);
  const auto header = decodeHeader(std::span<const unsigned char, kHeaderSize>(bytes.data(), kHeaderSize));
  ASSERT_TRUE(header);
  EXPECT_EQ(header->typeName(), "TRANSFORM");
  EXPECT_EQ(header->deviceName(), "Tool");
  ASSERT_EQ(header->bodySize, bytes.size() - kHeaderSize);
  const std::span<const unsigned char> body(bytes.data() + kHeaderSize, header->bodySize);
  EXPECT_EQ(crc64(body), header->crc);
  const auto transform = decodeTransform(*messageContent(*header, body));
  ASSERT_TRUE(transform);
  EXPECT_NEAR(transform->translation.x(), 12.5, 1e-6);
  EXPECT_NEAR(transform->translation.y(), -4.0, 1e-6);
  EXPECT_NEAR(transform->translation.z(), 80.25, 1e-6);
  EXPECT_NEAR(transform->rotation(1, 0), std::sin(0.3), 1e-6) << "row 1, column 0";
  EXPECT_NEAR(transform->rotation(0, 1), -std::sin(0.3), 1e-6);
}

TEST(IgtlMessagesTest, ASensorWrittenHereIsUnpackedByTheLibraryWithItsCrcAndUnit) {
  std::array<unsigned char, kForceSensorMessageSize> bytes{};
  encodeForceSensor("Force", toTimestamp(12.25), Vec3(0.5, -1.25, 3.3), bytes);
  auto header = igtl::MessageHeader::New();
  header->InitPack();
  std::memcpy(header->GetPackPointer(), bytes.data(), kHeaderSize);
  header->Unpack();
  EXPECT_STREQ(header->GetDeviceType(), "SENSOR");
  EXPECT_STREQ(header->GetDeviceName(), "Force");
  auto sensor = igtl::SensorMessage::New();
  sensor->SetMessageHeader(header);
  sensor->AllocatePack();
  std::memcpy(sensor->GetPackBodyPointer(), bytes.data() + kHeaderSize, sensor->GetPackBodySize());
  ASSERT_EQ(sensor->Unpack(1), igtl::MessageHeader::UNPACK_BODY) << "the CRC checks";
  ASSERT_EQ(sensor->GetLength(), 3u);
  EXPECT_EQ(sensor->GetValue(0), 0.5);
  EXPECT_EQ(sensor->GetValue(1), -1.25);
  EXPECT_EQ(sensor->GetValue(2), 3.3);
  igtl_unit_data unit;
  igtl_unit_unpack(sensor->GetUnit(), &unit);
  EXPECT_EQ(unit.prefix, IGTL_UNIT_PREFIX_NONE);
  EXPECT_EQ(unit.unit[0], IGTL_UNIT_SI_DERIVED_NEWTON);
  EXPECT_EQ(unit.exp[0], 1);
  EXPECT_EQ(unit.unit[1], IGTL_UNIT_SI_BASE_NONE);
  igtl_unit_data newton;
  igtl_unit_init(&newton);
  newton.unit[0] = IGTL_UNIT_SI_DERIVED_NEWTON;
  newton.exp[0] = 1;
  EXPECT_EQ(newtonUnit(), igtl_unit_pack(&newton));
}

// A version 2 message laid out by hand: the extended header (12 bytes), the
// content, then the metadata's header and the metadata.
std::vector<unsigned char> version2Transform(const std::vector<unsigned char>& content) {
  std::vector<unsigned char> body = {0, 12, 0, 2, 0, 0, 0, 5, 0, 0, 0, 9};  // ext 12, meta header 2, meta 5, id 9
  body.insert(body.end(), content.begin(), content.end());
  for (int i = 0; i < 7; ++i) body.push_back(static_cast<unsigned char>('a' + i));
  MessageHeader header;
  header.version = 2;
  std::memcpy(header.type.data(), "TRANSFORM", 9);
  std::memcpy(header.device.data(), "Tool", 4);
  header.bodySize = body.size();
  header.crc = crc64(body);
  std::vector<unsigned char> bytes(kHeaderSize);
  encodeHeader(header, std::span<unsigned char, kHeaderSize>(bytes.data(), kHeaderSize));
  bytes.insert(bytes.end(), body.begin(), body.end());
  return bytes;
}

TEST(IgtlMessagesTest, AStreamCutAnywhereReadsTheSameMessagesInEveryVersion) {
  const std::vector<unsigned char> v1 = packed(libraryTransform(0.1, 1, 2, 3));
  const std::vector<unsigned char> v2 = version2Transform({v1.begin() + kHeaderSize, v1.end()});
  auto status = igtl::SensorMessage::New();  // another type: skipped
  status->SetDeviceName("Other");
  status->SetLength(4);
  std::vector<unsigned char> stream;
  for (const auto* part : {&v1, &v2}) stream.insert(stream.end(), part->begin(), part->end());
  const std::vector<unsigned char> other = packed(status);
  stream.insert(stream.end(), other.begin(), other.end());
  stream.insert(stream.end(), v1.begin(), v1.end());

  std::mt19937 random(3);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<Vec3> translations;
    IgtlStreamReader reader([](const MessageHeader& h) { return h.typeName() == "TRANSFORM"; },
                            [&](const MessageHeader&, std::span<const unsigned char> content) {
                              const auto t = decodeTransform(content);
                              ASSERT_TRUE(t);
                              translations.push_back(t->translation);
                            });
    size_t at = 0;
    while (at < stream.size()) {
      const size_t take = std::min<size_t>(stream.size() - at, 1 + random() % 97);
      ASSERT_TRUE(reader.feed({stream.data() + at, take})) << reader.error();
      at += take;
    }
    ASSERT_EQ(translations.size(), 3u);
    for (const Vec3& t : translations) EXPECT_EQ(t, Vec3(1, 2, 3));
    EXPECT_EQ(reader.messagesSkipped(), 1u);
  }
}

TEST(IgtlMessagesTest, AStreamThatBreaksTheProtocolIsRefusedSayingHow) {
  const auto read = [](std::vector<unsigned char> bytes) {
    IgtlStreamReader reader([](const MessageHeader& h) { return h.typeName() == "TRANSFORM"; },
                            [](const MessageHeader&, std::span<const unsigned char>) {});
    reader.feed(bytes);
    return reader.error();
  };
  std::vector<unsigned char> good = packed(libraryTransform(0.1, 1, 2, 3));
  EXPECT_EQ(read(good), "");
  auto bad = good;
  bad[1] = 7;  // version 7
  EXPECT_NE(read(bad).find("not an OpenIGTLink header"), std::string::npos);
  bad = good;
  bad[3] = 0x01;  // a control character in the type name
  EXPECT_NE(read(bad).find("not an OpenIGTLink header"), std::string::npos);
  bad = good;
  bad.back() ^= 1;  // the body no longer matches its CRC
  EXPECT_NE(read(bad).find("CRC"), std::string::npos);
  bad = good;
  bad[42] = 0x10;  // a body of 2^60 bytes
  EXPECT_NE(read(bad).find("bytes"), std::string::npos);
  std::vector<unsigned char> v2 = version2Transform({good.begin() + kHeaderSize, good.end()});
  v2[kHeaderSize + 1] = 200;  // an extended header longer than the body
  MessageHeader h = *decodeHeader(std::span<const unsigned char, kHeaderSize>(v2.data(), kHeaderSize));
  h.crc = crc64({v2.data() + kHeaderSize, v2.size() - kHeaderSize});
  encodeHeader(h, std::span<unsigned char, kHeaderSize>(v2.data(), kHeaderSize));
  EXPECT_NE(read(v2).find("extended header"), std::string::npos);
}

TEST(IgtlMessagesTest, ATransformThatIsNotRigidOrFiniteIsRefused) {
  const auto content = [](const auto& spoil) {
    auto message = libraryTransform(0.0, 1, 2, 3);
    igtl::Matrix4x4 m;
    message->GetMatrix(m);
    spoil(m);
    message->SetMatrix(m);
    std::vector<unsigned char> bytes = packed(message);
    return std::vector<unsigned char>(bytes.begin() + kHeaderSize, bytes.end());
  };
  EXPECT_TRUE(decodeTransform(content([](igtl::Matrix4x4&) {})));
  EXPECT_FALSE(decodeTransform(content([](igtl::Matrix4x4& m) { m[0][0] = 2; })));   // stretched
  EXPECT_FALSE(decodeTransform(content([](igtl::Matrix4x4& m) { m[2][2] = -1; })));  // a mirror
  EXPECT_FALSE(decodeTransform(content([](igtl::Matrix4x4& m) { m[0][3] = NAN; })));
  EXPECT_FALSE(decodeTransform(std::vector<unsigned char>(47)));
}

}  // namespace
}  // namespace trephine::openigtlink
