// The capped zlib/gzip inflater the file readers share: round trips, joined
// gzip members, truncated and corrupt streams, the cap, and exact blocks.
#include <gtest/gtest.h>
#include <zlib.h>

#include <string>
#include <vector>

#include "framework/formats/encoding/Inflate.h"
#include "tests/support/ZlibStream.h"

namespace trephine::formats {
namespace {

// Deflates `text` with a zlib (windowBits 15) or gzip (15 + 16) wrapper.
std::vector<uint8_t> deflated(const std::string& text, int windowBits) {
  return test::zlibStream(text, test::ZlibWrapper(windowBits));
}

std::string patterned(size_t n) {
  std::string text;
  for (size_t i = 0; text.size() < n; ++i) text += "node " + std::to_string(i * 7919 % 100003) + "\n";
  text.resize(n);
  return text;
}

struct Output {
  std::string bytes;
  Inflated result;
};
Output inflate(const std::vector<uint8_t>& compressed, uint64_t maxBytes) {
  Output o;
  o.result = inflateInto(compressed, maxBytes, [&](size_t n) {
    o.bytes.resize(n);
    return reinterpret_cast<uint8_t*>(o.bytes.data());
  });
  return o;
}

TEST(InflateTest, ZlibAndGzipRoundTripAndGzipMembersJoin) {
  const std::string text = patterned(300000);  // more than the first output buffer
  for (int windowBits : {15, 15 + 16}) {
    const Output o = inflate(deflated(text, windowBits), 1u << 30);
    EXPECT_TRUE(o.result.streamEnded);
    EXPECT_FALSE(o.result.exceeded);
    EXPECT_EQ(o.bytes, text);
  }
  std::vector<uint8_t> two = deflated("first,", 31);
  const std::vector<uint8_t> second = deflated("second", 31);
  two.insert(two.end(), second.begin(), second.end());
  two.push_back('x');  // trailing bytes that are not gzip are ignored
  EXPECT_EQ(inflate(two, 1000).bytes, "first,second");
}

TEST(InflateTest, TruncatedStreamsEndWithoutTheirMarker) {
  std::vector<uint8_t> compressed = deflated(patterned(50000), 31);
  compressed.resize(compressed.size() / 2);
  const Output o = inflate(compressed, 1u << 30);
  EXPECT_FALSE(o.result.streamEnded);
  EXPECT_FALSE(o.result.exceeded);
  EXPECT_GT(o.bytes.size(), 0u);
  EXPECT_EQ(o.bytes.size(), o.result.size);
}

TEST(InflateTest, TheCapStopsAStreamThatHoldsMore) {
  const std::string text = patterned(100000);
  const Output capped = inflate(deflated(text, 15), 4096);
  EXPECT_TRUE(capped.result.exceeded);
  EXPECT_EQ(capped.bytes, text.substr(0, 4096));
  const Output exact = inflate(deflated(text, 15), text.size());  // a stream exactly at the cap is whole
  EXPECT_TRUE(exact.result.streamEnded);
  EXPECT_FALSE(exact.result.exceeded);
}

TEST(InflateTest, CorruptDataIsAnInflateErrorWithZlibsReason) {
  std::vector<uint8_t> compressed = deflated(patterned(20000), 15);
  for (size_t i = 2; i < 12; ++i) compressed[i] ^= 0xA5;
  EXPECT_THROW(inflate(compressed, 1u << 20), InflateError);
  EXPECT_THROW(inflate({0x12, 0x34, 0x56, 0x78}, 1000), InflateError) << "no zlib or gzip header";
}

TEST(InflateTest, ExactBlocksSayWhatIsWrong) {
  const std::string text = patterned(1000);
  const std::vector<uint8_t> block = deflated(text, 15);
  std::vector<uint8_t> out(text.size());
  EXPECT_FALSE(inflateExactly(block, out).has_value());
  EXPECT_EQ(std::string(out.begin(), out.end()), text);
  std::vector<uint8_t> small(999), large(1001);
  EXPECT_NE(inflateExactly(block, small).value_or("").find("holds more than the 999 bytes"), std::string::npos);
  EXPECT_NE(inflateExactly(block, large).value_or("").find("holds 1000 bytes, expected 1001"), std::string::npos);
  EXPECT_NE(inflateExactly(std::span(block).first(8), out).value_or("").find("ends early"), std::string::npos);
  std::vector<uint8_t> huge(100000);  // 8 compressed bytes hold at most 8 * 1032 + 1024
  EXPECT_NE(inflateExactly(std::span(block).first(8), huge).value_or("").find("cannot hold"), std::string::npos);
}

}  // namespace
}  // namespace trephine::formats
