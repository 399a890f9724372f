// The device bridge over shared memory (plugins/device_bridge/c): two
// mappings of one object (as the device program's and the simulation's
// would be) see each other's latest packet; a bad name, a missing object and
// one of another size are refused with their reason; and a writer racing a
// reader never hands it a torn packet (threaded: run under ThreadSanitizer).
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>

#include "trephine_bridge_shm.h"

namespace {

std::string uniqueName(const char* what) { return "/trephine-test-" + std::string(what) + "-" + std::to_string(getpid()); }

std::array<unsigned char, TREPHINE_BRIDGE_POSE_SIZE> posePacket(uint64_t sequence) {
  trephine_bridge_pose pose{};
  pose.sequence = sequence;
  pose.device_time_ns = 1000 * sequence;
  pose.position_mm[0] = double(sequence % 1000) * 0.01;
  // A quaternion that turns with the sequence: a torn packet mixing two
  // would not be a unit quaternion, or not the sequence's own.
  const double angle = double(sequence % 628) * 0.01;
  pose.orientation_wxyz[0] = std::cos(angle / 2);
  pose.orientation_wxyz[3] = std::sin(angle / 2);
  std::array<unsigned char, TREPHINE_BRIDGE_POSE_SIZE> bytes{};
  EXPECT_EQ(trephine_bridge_encode_pose(&pose, bytes.data()), TREPHINE_BRIDGE_OK);
  return bytes;
}

TEST(BridgeSharedMemoryTest, TwoMappingsSeeEachOthersLatestPacket) {
  const std::string name = uniqueName("mappings");
  int error = 0;
  trephine_bridge_shm* simulation = trephine_bridge_shm_open(name.c_str(), 1, &error);
  ASSERT_NE(simulation, nullptr) << std::strerror(error);
  trephine_bridge_shm* device = trephine_bridge_shm_open(name.c_str(), 0, &error);
  ASSERT_NE(device, nullptr) << std::strerror(error);
  std::array<unsigned char, TREPHINE_BRIDGE_POSE_SIZE> read{};
  EXPECT_EQ(trephine_bridge_shm_read_pose(simulation, read.data()), 0) << "nothing written yet";
  for (uint64_t sequence : {1u, 2u, 3u}) trephine_bridge_shm_write_pose(device, posePacket(sequence).data());
  ASSERT_EQ(trephine_bridge_shm_read_pose(simulation, read.data()), 1);
  EXPECT_EQ(read, posePacket(3)) << "the latest";
  trephine_bridge_force force{};
  force.answered_sequence = 3;
  force.force_n[2] = 1.25;
  std::array<unsigned char, TREPHINE_BRIDGE_FORCE_SIZE> forceBytes{}, forceRead{};
  ASSERT_EQ(trephine_bridge_encode_force(&force, forceBytes.data()), TREPHINE_BRIDGE_OK);
  trephine_bridge_shm_write_force(simulation, forceBytes.data());
  ASSERT_EQ(trephine_bridge_shm_read_force(device, forceRead.data()), 1);
  EXPECT_EQ(forceRead, forceBytes);
  trephine_bridge_shm_close(device, name.c_str(), 0);
  trephine_bridge_shm_close(simulation, name.c_str(), 1);
  EXPECT_EQ(trephine_bridge_shm_open(name.c_str(), 0, &error), nullptr) << "removed by its creator";
  EXPECT_EQ(error, ENOENT);
}

TEST(BridgeSharedMemoryTest, ABadNameAMissingObjectAndAForeignOneAreRefused) {
  int error = 0;
  EXPECT_EQ(trephine_bridge_shm_open("no-slash", 1, &error), nullptr);
  EXPECT_EQ(error, EINVAL);
  EXPECT_EQ(trephine_bridge_shm_open("/a/b", 1, &error), nullptr);
  EXPECT_EQ(error, EINVAL);
  EXPECT_EQ(trephine_bridge_shm_open(uniqueName("missing").c_str(), 0, &error), nullptr);
  EXPECT_EQ(error, ENOENT);
  // Another program's object of that name, of another size.
  const std::string name = uniqueName("foreign");
  const int fd = shm_open(name.c_str(), O_RDWR | O_CREAT, 0600);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(ftruncate(fd, 4096), 0);
  close(fd);
  EXPECT_EQ(trephine_bridge_shm_open(name.c_str(), 1, &error), nullptr);
  EXPECT_EQ(error, EPROTO);
  shm_unlink(name.c_str());
}

TEST(BridgeSharedMemoryTest, AWriterRacingAReaderNeverHandsItATornPacket) {
  const std::string name = uniqueName("race");
  int error = 0;
  trephine_bridge_shm* reader = trephine_bridge_shm_open(name.c_str(), 1, &error);
  ASSERT_NE(reader, nullptr) << std::strerror(error);
  trephine_bridge_shm* writer = trephine_bridge_shm_open(name.c_str(), 0, &error);
  ASSERT_NE(writer, nullptr);
  constexpr uint64_t kPackets = 200000;
  std::atomic<bool> done{false};
  std::atomic<uint64_t> wholeSeen{0}, lastWritten{0};
  // The writer goes on past kPackets until the reader has had 100 whole
  // packets, so that a machine busy elsewhere cannot starve the race.
  std::thread device([&] {
    uint64_t sequence = 1;
    for (; sequence <= kPackets || wholeSeen.load(std::memory_order_relaxed) < 100; ++sequence)
      trephine_bridge_shm_write_pose(writer, posePacket(sequence).data());
    lastWritten = sequence - 1;
    done = true;
  });
  uint64_t whole = 0, last = 0, torn = 0, backwards = 0;
  std::array<unsigned char, TREPHINE_BRIDGE_POSE_SIZE> bytes{};
  while (!done.load() || whole == 0) {
    if (!trephine_bridge_shm_read_pose(reader, bytes.data())) continue;
    trephine_bridge_pose pose{};
    if (trephine_bridge_decode_pose(bytes.data(), bytes.size(), &pose) != TREPHINE_BRIDGE_OK ||
        bytes != posePacket(pose.sequence)) {
      ++torn;
      continue;
    }
    backwards += pose.sequence < last;
    last = pose.sequence;
    wholeSeen = ++whole;
  }
  device.join();
  ASSERT_EQ(trephine_bridge_shm_read_pose(reader, bytes.data()), 1);
  EXPECT_EQ(bytes, posePacket(lastWritten.load())) << "the last one written";
  EXPECT_EQ(torn, 0u);
  EXPECT_EQ(backwards, 0u);
  EXPECT_GE(whole, 100u);
  trephine_bridge_shm_close(writer, name.c_str(), 0);
  trephine_bridge_shm_close(reader, name.c_str(), 1);
}

}  // namespace
