// The device bridge's packets (plugins/device_bridge/c): the bytes of a pose
// and a force as the header lays them out (written here byte by byte, not by
// the encoder), round trips, every malformation refused with its reason and
// nothing written, and sequence numbers across their wrap.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "trephine_bridge.h"

namespace {

using Bytes = std::vector<unsigned char>;

void putLittle(Bytes& out, uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<unsigned char>(value >> (8 * i)));
}
void putDouble(Bytes& out, double value) {
  uint64_t bits;
  std::memcpy(&bits, &value, 8);
  putLittle(out, bits, 8);
}

// A pose packet as the header's table lays it out.
Bytes poseBytes(uint64_t sequence, uint64_t time, std::array<double, 3> p, std::array<double, 4> q, uint32_t buttons,
               uint32_t roundTripNs = 0, uint64_t session = 0x5E55, uint64_t heardSession = 0,
               uint64_t heardSequence = 0) {
  Bytes b;
  for (const char c : {'T', 'R', 'P', 'B'}) b.push_back(static_cast<unsigned char>(c));
  putLittle(b, 2, 2);
  putLittle(b, 1, 2);
  putLittle(b, sequence, 8);
  putLittle(b, time, 8);
  for (const double v : p) putDouble(b, v);
  for (const double v : q) putDouble(b, v);
  putLittle(b, buttons, 4);
  putLittle(b, roundTripNs, 4);
  putLittle(b, session, 8);
  putLittle(b, heardSession, 8);
  putLittle(b, heardSequence, 8);
  return b;
}

trephine_bridge_pose samplePose() {
  trephine_bridge_pose pose{};
  pose.sequence = 0x0102030405060708ull;
  pose.device_time_ns = 123456789012ull;
  pose.position_mm[0] = 12.5;
  pose.position_mm[1] = -3.25;
  pose.position_mm[2] = 80.0;
  const double h = std::sqrt(0.5);
  pose.orientation_wxyz[0] = h;
  pose.orientation_wxyz[3] = h;
  pose.buttons = 0b101;
  pose.round_trip_ns = 0xA1B2C3u;
  pose.session = 0x1122334455667788ull;
  pose.heard_session = 0x99AABBCCDDEEFF00ull;
  pose.heard_sequence = 4242;
  return pose;
}

TEST(BridgePacketsTest, APoseIsTheBytesTheHeaderLaysOut) {
  const trephine_bridge_pose pose = samplePose();
  std::array<unsigned char, TREPHINE_BRIDGE_POSE_SIZE> encoded{};
  ASSERT_EQ(trephine_bridge_encode_pose(&pose, encoded.data()), TREPHINE_BRIDGE_OK);
  const Bytes expected = poseBytes(pose.sequence, pose.device_time_ns, {12.5, -3.25, 80.0},
                                   {std::sqrt(0.5), 0, 0, std::sqrt(0.5)}, 0b101, 0xA1B2C3u,
                                   0x1122334455667788ull, 0x99AABBCCDDEEFF00ull, 4242);
  ASSERT_EQ(expected.size(), TREPHINE_BRIDGE_POSE_SIZE);
  EXPECT_EQ(Bytes(encoded.begin(), encoded.end()), expected);
  trephine_bridge_pose decoded{};
  ASSERT_EQ(trephine_bridge_decode_pose(expected.data(), expected.size(), &decoded), TREPHINE_BRIDGE_OK);
  EXPECT_EQ(decoded.sequence, pose.sequence);
  EXPECT_EQ(decoded.device_time_ns, pose.device_time_ns);
  EXPECT_EQ(decoded.buttons, 0b101u);
  EXPECT_EQ(decoded.round_trip_ns, 0xA1B2C3u) << "the device's last round trip at 84";
  EXPECT_EQ(decoded.session, 0x1122334455667788ull) << "its session at 88";
  EXPECT_EQ(decoded.heard_session, 0x99AABBCCDDEEFF00ull) << "the simulation's session it takes, at 96";
  EXPECT_EQ(decoded.heard_sequence, 4242u) << "the last force it took, at 104";
  for (int i = 0; i < 3; ++i) EXPECT_EQ(decoded.position_mm[i], pose.position_mm[i]);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(decoded.orientation_wxyz[i], pose.orientation_wxyz[i]);
}

TEST(BridgePacketsTest, AForceRoundTripsExactlyAndLiesWhereTheHeaderSays) {
  trephine_bridge_force force{};
  force.sequence = 7;
  force.answered_sequence = 41;
  force.answered_device_time_ns = 999;
  force.simulation_time_ns = 5000000;
  force.force_n[0] = -1.5;
  force.force_n[1] = 0.25;
  force.force_n[2] = 3.3;
  force.flags = TREPHINE_BRIDGE_FORCE_CLAMPED;
  force.session = 0xABCDEF;
  std::array<unsigned char, TREPHINE_BRIDGE_FORCE_SIZE> encoded{};
  ASSERT_EQ(trephine_bridge_encode_force(&force, encoded.data()), TREPHINE_BRIDGE_OK);
  EXPECT_EQ(encoded[6], 2) << "kind 2";
  EXPECT_EQ(encoded[16], 41) << "the answered pose's sequence at 16";
  double fz;
  std::memcpy(&fz, encoded.data() + 56, 8);  // the machine here is little-endian
  EXPECT_EQ(fz, 3.3) << "force z at 56";
  EXPECT_EQ(encoded[64], TREPHINE_BRIDGE_FORCE_CLAMPED) << "flags at 64";
  EXPECT_EQ(encoded[72], 0xEF) << "the simulation's session at 72";
  EXPECT_EQ(encoded[4], 2) << "version 2";
  trephine_bridge_force decoded{};
  ASSERT_EQ(trephine_bridge_decode_force(encoded.data(), encoded.size(), &decoded), TREPHINE_BRIDGE_OK);
  EXPECT_EQ(std::memcmp(&decoded.force_n, &force.force_n, sizeof force.force_n), 0);
  EXPECT_EQ(decoded.answered_sequence, 41u);
  EXPECT_EQ(decoded.answered_device_time_ns, 999u);
  EXPECT_EQ(decoded.simulation_time_ns, 5000000u);
  EXPECT_EQ(decoded.flags, TREPHINE_BRIDGE_FORCE_CLAMPED);
  EXPECT_EQ(decoded.session, 0xABCDEFu);
}

TEST(BridgePacketsTest, EveryMalformationIsRefusedWithItsReasonAndNothingWritten) {
  const trephine_bridge_pose pose = samplePose();
  std::array<unsigned char, TREPHINE_BRIDGE_POSE_SIZE> good{};
  ASSERT_EQ(trephine_bridge_encode_pose(&pose, good.data()), TREPHINE_BRIDGE_OK);
  const auto decode = [](Bytes bytes) {
    trephine_bridge_pose out{};
    out.sequence = 77;  // a decode that fails leaves it
    const trephine_bridge_status status = trephine_bridge_decode_pose(bytes.data(), bytes.size(), &out);
    EXPECT_TRUE(status == TREPHINE_BRIDGE_OK || out.sequence == 77u) << trephine_bridge_status_text(status);
    return status;
  };
  const Bytes ok(good.begin(), good.end());
  EXPECT_EQ(decode(ok), TREPHINE_BRIDGE_OK);
  EXPECT_EQ(decode(Bytes(ok.begin(), ok.end() - 1)), TREPHINE_BRIDGE_WRONG_SIZE);
  Bytes longer = ok;
  longer.push_back(0);
  EXPECT_EQ(decode(longer), TREPHINE_BRIDGE_WRONG_SIZE);
  EXPECT_EQ(decode(Bytes(ok.begin(), ok.begin() + 3)), TREPHINE_BRIDGE_WRONG_SIZE);
  Bytes b = ok;
  b[0] = 'X';
  EXPECT_EQ(decode(b), TREPHINE_BRIDGE_BAD_MAGIC);
  b = ok;
  b[4] = 1;
  EXPECT_EQ(decode(b), TREPHINE_BRIDGE_BAD_VERSION) << "version 1, without sessions";
  b = ok;
  b[6] = 2;
  EXPECT_EQ(decode(b), TREPHINE_BRIDGE_BAD_KIND) << "a force is not a pose";
  b = ok;
  b[84] = 1;
  EXPECT_EQ(decode(b), TREPHINE_BRIDGE_OK) << "bytes 84 to 87 are the device's round trip";
  EXPECT_EQ(decode(poseBytes(1, 0, {0, 0, 0}, {1, 0, 0, 0}, 0, 0, /*session=*/0)), TREPHINE_BRIDGE_NO_SESSION);
  const auto withPosition = [&](double x) {
    return poseBytes(1, 0, {x, 0, 0}, {1, 0, 0, 0}, 0);
  };
  EXPECT_EQ(decode(withPosition(std::numeric_limits<double>::quiet_NaN())), TREPHINE_BRIDGE_NOT_FINITE);
  EXPECT_EQ(decode(withPosition(std::numeric_limits<double>::infinity())), TREPHINE_BRIDGE_NOT_FINITE);
  EXPECT_EQ(decode(withPosition(1e5)), TREPHINE_BRIDGE_OUT_OF_RANGE);
  EXPECT_EQ(decode(withPosition(-9999.0)), TREPHINE_BRIDGE_OK);
  EXPECT_EQ(decode(poseBytes(1, 0, {0, 0, 0}, {1.01, 0, 0, 0}, 0)), TREPHINE_BRIDGE_NOT_UNIT);
  EXPECT_EQ(decode(poseBytes(1, 0, {0, 0, 0}, {0, 0, 0, 0}, 0)), TREPHINE_BRIDGE_NOT_UNIT);
  EXPECT_EQ(decode(poseBytes(1, 0, {0, 0, 0}, {1.0005, 0, 0, 0}, 0)), TREPHINE_BRIDGE_OK) << "within 1e-3";
  // A sender cannot write what the other end would refuse.
  trephine_bridge_pose bad = pose;
  bad.orientation_wxyz[0] = 2;
  std::array<unsigned char, TREPHINE_BRIDGE_POSE_SIZE> untouched{};
  EXPECT_EQ(trephine_bridge_encode_pose(&bad, untouched.data()), TREPHINE_BRIDGE_NOT_UNIT);
  EXPECT_EQ(untouched, (std::array<unsigned char, TREPHINE_BRIDGE_POSE_SIZE>{}));
  trephine_bridge_force force{};
  force.session = 1;
  force.force_n[1] = std::numeric_limits<double>::quiet_NaN();
  std::array<unsigned char, TREPHINE_BRIDGE_FORCE_SIZE> forceBytes{};
  EXPECT_EQ(trephine_bridge_encode_force(&force, forceBytes.data()), TREPHINE_BRIDGE_NOT_FINITE) << "never a NaN sent";
  force.force_n[1] = 2000;
  EXPECT_EQ(trephine_bridge_encode_force(&force, forceBytes.data()), TREPHINE_BRIDGE_OUT_OF_RANGE);
  force.force_n[1] = 0;
  force.session = 0;
  EXPECT_EQ(trephine_bridge_encode_force(&force, forceBytes.data()), TREPHINE_BRIDGE_NO_SESSION);
  EXPECT_EQ(trephine_bridge_decode_pose(nullptr, 112, nullptr), TREPHINE_BRIDGE_NULL);
  EXPECT_STREQ(trephine_bridge_status_text(TREPHINE_BRIDGE_NOT_UNIT), "an orientation that is not a unit quaternion");
}

// Random bytes of every length up to both sizes, and single bit flips of a
// good packet: the decoder never reads past the size (AddressSanitizer
// checks it), and whatever it accepts is valid.
TEST(BridgePacketsTest, RandomBytesAndBitFlipsAreRefusedOrValid) {
  std::mt19937_64 random(5);
  const trephine_bridge_pose pose = samplePose();
  std::array<unsigned char, TREPHINE_BRIDGE_POSE_SIZE> good{};
  ASSERT_EQ(trephine_bridge_encode_pose(&pose, good.data()), TREPHINE_BRIDGE_OK);
  int accepted = 0;
  for (size_t bit = 0; bit < 8 * good.size(); ++bit) {
    std::vector<unsigned char> flipped(good.begin(), good.end());
    flipped[bit / 8] ^= static_cast<unsigned char>(1u << (bit % 8));
    trephine_bridge_pose out{};
    if (trephine_bridge_decode_pose(flipped.data(), flipped.size(), &out) != TREPHINE_BRIDGE_OK) continue;
    ++accepted;
    double norm = 0;
    for (const double c : out.orientation_wxyz) norm += c * c;
    EXPECT_LT(std::abs(std::sqrt(norm) - 1), 1.001e-3);
    for (const double p : out.position_mm) EXPECT_TRUE(std::isfinite(p) && std::abs(p) <= 1e4);
  }
  EXPECT_GT(accepted, 0) << "flips of the sequence, time and buttons are valid packets";
  for (int round = 0; round < 20000; ++round) {
    std::vector<unsigned char> bytes(random() % (TREPHINE_BRIDGE_POSE_SIZE + 8));
    for (unsigned char& c : bytes) c = static_cast<unsigned char>(random());
    if (bytes.size() >= 8 && random() % 2) std::memcpy(bytes.data(), good.data(), 8);  // past the header
    trephine_bridge_pose pose{};
    trephine_bridge_force force{};
    trephine_bridge_decode_pose(bytes.data(), bytes.size(), &pose);
    trephine_bridge_decode_force(bytes.data(), bytes.size(), &force);
  }
}

TEST(BridgePacketsTest, SequencesCompareAcrossTheirWrap) {
  EXPECT_TRUE(trephine_bridge_is_newer(1, 2));
  EXPECT_FALSE(trephine_bridge_is_newer(2, 2)) << "a repeat is not newer";
  EXPECT_FALSE(trephine_bridge_is_newer(5, 3)) << "reordered: older";
  const uint64_t top = std::numeric_limits<uint64_t>::max();
  EXPECT_TRUE(trephine_bridge_is_newer(top, 0)) << "the wrap";
  EXPECT_TRUE(trephine_bridge_is_newer(top - 3, 2));
  EXPECT_FALSE(trephine_bridge_is_newer(2, top - 3));
}

// A receiver's stream: one session at a time, sequences judged against time.
TEST(BridgePacketsTest, AStreamTakesOneSessionAtATimeAndJudgesJumpsAgainstTime) {
  constexpr uint64_t ms = 1000000;
  trephine_bridge_stream stream;
  trephine_bridge_stream_init(&stream, 0.05, 10000);  // quiet 50 ms; at most 10 kHz
  const uint64_t device = 0xD1, stranger = 0x5A, restarted = 0xD2;
  EXPECT_EQ(trephine_bridge_stream_judge(&stream, device, 1, 0), TREPHINE_BRIDGE_NEW_SESSION) << "none yet";
  trephine_bridge_stream_take(&stream, device, 1, 0);
  EXPECT_EQ(trephine_bridge_stream_judge(&stream, device, 2, 1 * ms), TREPHINE_BRIDGE_TAKE);
  EXPECT_EQ(trephine_bridge_stream_judge(&stream, device, 1, 1 * ms), TREPHINE_BRIDGE_STALE);
  // A jump of 2^62 is never what 1 ms explains; 10 sequences are (slack), and 64 + 10 kHz x 10 ms are.
  EXPECT_EQ(trephine_bridge_stream_judge(&stream, device, uint64_t(1) << 62, 1 * ms), TREPHINE_BRIDGE_TOO_FAR_AHEAD);
  EXPECT_EQ(trephine_bridge_stream_judge(&stream, device, 11, 1 * ms), TREPHINE_BRIDGE_TAKE);
  EXPECT_EQ(trephine_bridge_stream_judge(&stream, device, 1 + 64 + 100, 10 * ms), TREPHINE_BRIDGE_TAKE);
  EXPECT_EQ(trephine_bridge_stream_judge(&stream, device, 1 + 64 + 102, 10 * ms), TREPHINE_BRIDGE_TOO_FAR_AHEAD);
  // Another session is not taken while the one taken is heard, whatever its sequence ...
  EXPECT_EQ(trephine_bridge_stream_judge(&stream, stranger, uint64_t(1) << 62, 49 * ms), TREPHINE_BRIDGE_OTHER_SESSION);
  trephine_bridge_stream_take(&stream, device, 50, 40 * ms);
  EXPECT_EQ(trephine_bridge_stream_judge(&stream, restarted, 1, 80 * ms), TREPHINE_BRIDGE_OTHER_SESSION);
  // ... and is once it went quiet for the quiet time (the device program started again).
  EXPECT_EQ(trephine_bridge_stream_judge(&stream, restarted, 1, 90 * ms), TREPHINE_BRIDGE_NEW_SESSION);
  trephine_bridge_stream_take(&stream, restarted, 1, 90 * ms);
  EXPECT_EQ(trephine_bridge_stream_judge(&stream, restarted, 2, 91 * ms), TREPHINE_BRIDGE_TAKE);
  EXPECT_EQ(trephine_bridge_stream_judge(&stream, device, 51, 91 * ms), TREPHINE_BRIDGE_OTHER_SESSION)
      << "the earlier session's late packets are not taken";
  EXPECT_EQ(stream.sessions, 2u);
}

TEST(BridgePacketsTest, NewSessionsAreNeverZeroAndDiffer) {
  std::vector<uint64_t> sessions;
  for (int k = 0; k < 1000; ++k) sessions.push_back(trephine_bridge_new_session());
  for (const uint64_t s : sessions) EXPECT_NE(s, 0u);
  std::sort(sessions.begin(), sessions.end());
  EXPECT_EQ(std::unique(sessions.begin(), sessions.end()), sessions.end());
}

}  // namespace
