// The device bridge over shared memory (plugins/device_bridge/c): two
// mappings of one object (as the device program's and the simulation's
// would be) see each other's latest packet; a bad name, a missing object and
// one of another size are refused with their reason; and a writer racing a
// reader never hands it a torn packet (threaded: run under ThreadSanitizer).
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>

#include "trephine_bridge_shm.h"

// ThreadSanitizer, as clang says it.
#if defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define TREPHINE_TSAN 1
#endif
#endif
#ifndef TREPHINE_TSAN
#define TREPHINE_TSAN 0
#endif

namespace {

std::string uniqueName(const char* what) { return "/trephine-test-" + std::string(what) + "-" + std::to_string(getpid()); }

std::array<unsigned char, TREPHINE_BRIDGE_POSE_SIZE> posePacket(uint64_t sequence) {
  trephine_bridge_pose pose{};
  pose.sequence = sequence;
  pose.session = 0xD5;
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
  force.session = 0x51;
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

// An object made beforehand by someone else (another user, or open to all)
// is never taken: whoever can write it would drive the device and read its
// forces. The bridge's own object is owner-only.
TEST(BridgeSharedMemoryTest, AnObjectOpenToOthersOrOfAnotherUserIsRefused) {
  int error = 0;
  const std::string name = uniqueName("planted");
  trephine_bridge_shm* made = trephine_bridge_shm_open(name.c_str(), 1, &error);
  ASSERT_NE(made, nullptr) << std::strerror(error);
  struct stat st {};
  const int own = shm_open(name.c_str(), O_RDWR, 0);
  ASSERT_GE(own, 0);
  ASSERT_EQ(fstat(own, &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u) << "made owner-only";
  // Opened to everyone after the fact (as a planted one would be): refused on both sides.
  ASSERT_EQ(fchmod(own, 0666), 0);
  EXPECT_EQ(trephine_bridge_shm_open(name.c_str(), 1, &error), nullptr);
  EXPECT_EQ(error, EPERM);
  EXPECT_EQ(trephine_bridge_shm_open(name.c_str(), 0, &error), nullptr);
  EXPECT_EQ(error, EPERM);
  ASSERT_EQ(fchmod(own, 0600), 0);
  if (geteuid() == 0) {
    // Owner-only, but another user's (nobody's).
    ASSERT_EQ(fchown(own, 65534, 65534), 0);
    EXPECT_EQ(trephine_bridge_shm_open(name.c_str(), 1, &error), nullptr);
    EXPECT_EQ(error, EPERM);
  }
  close(own);
  trephine_bridge_shm_close(made, name.c_str(), 1);
}

// Another process truncates the object while it is mapped: reading it would
// end this process with SIGBUS. The check each tick says it is gone, and a
// read in the moment before the check (the guard) reads "never written".
TEST(BridgeSharedMemoryTest, ATruncatedObjectIsSeenGoneAndNeverEndsTheProcess) {
  int error = 0;
  const std::string name = uniqueName("truncated");
  trephine_bridge_shm* shm = trephine_bridge_shm_open(name.c_str(), 1, &error);
  ASSERT_NE(shm, nullptr) << std::strerror(error);
  ASSERT_EQ(trephine_bridge_shm_guard_truncation(shm), 0);
  trephine_bridge_shm_write_pose(shm, posePacket(5).data());
  EXPECT_EQ(trephine_bridge_shm_intact(shm), 1);
  const int other = shm_open(name.c_str(), O_RDWR, 0);
  ASSERT_GE(other, 0);
  ASSERT_EQ(ftruncate(other, 0), 0);
  close(other);
  std::array<unsigned char, TREPHINE_BRIDGE_POSE_SIZE> read{};
#if !defined(__SANITIZE_THREAD__) && !TREPHINE_TSAN
  // Read before any check: the guard catches the fault. (Not under
  // ThreadSanitizer, whose own handling of a fault in a signal it defers
  // is not what is tested here.)
  EXPECT_EQ(trephine_bridge_shm_pose_writes(shm), 0u);
  EXPECT_EQ(trephine_bridge_shm_read_pose(shm, read.data()), 0);
#endif
  EXPECT_EQ(trephine_bridge_shm_intact(shm), 0);
  trephine_bridge_shm_write_force(shm, read.data());  // nothing happens: it is gone
  trephine_bridge_shm_close(shm, name.c_str(), 1);
  // Without the guard, the check alone: gone before anything is touched.
  shm = trephine_bridge_shm_open(name.c_str(), 1, &error);
  ASSERT_NE(shm, nullptr);
  const int again = shm_open(name.c_str(), O_RDWR, 0);
  ASSERT_EQ(ftruncate(again, 8), 0);
  close(again);
  EXPECT_EQ(trephine_bridge_shm_intact(shm), 0);
  EXPECT_EQ(trephine_bridge_shm_read_pose(shm, read.data()), 0);
  trephine_bridge_shm_close(shm, name.c_str(), 1);
}

// A claim naming a live process that is not the simulation that claimed it
// (its pid was given to another process since): replaced, by start time.
TEST(BridgeSharedMemoryTest, AClaimOfAPidNowAnotherProcesssIsReplaced) {
  int error = 0;
  const std::string name = uniqueName("claim");
  trephine_bridge_shm* shm = trephine_bridge_shm_open(name.c_str(), 1, &error);
  ASSERT_NE(shm, nullptr);
  // The parent (alive, started before this process) as a claim made by a
  // process that started when this one did.
  const long parent = static_cast<long>(getppid());
  EXPECT_EQ(trephine_bridge_shm_claim(shm, static_cast<long>(getpid())), 0);
  trephine_bridge_shm_release(shm, static_cast<long>(getpid()));
  EXPECT_EQ(trephine_bridge_shm_claim(shm, parent), 0) << "the parent holds it now, with its own start time";
  EXPECT_EQ(trephine_bridge_shm_claim(shm, static_cast<long>(getpid())), parent) << "a live holder keeps it";
  // Its start time rewritten, as if the pid were reused: no longer the holder.
  const int fd = shm_open(name.c_str(), O_RDWR, 0);
  struct stat st {};
  ASSERT_EQ(fstat(fd, &st), 0);
  void* memory = mmap(nullptr, size_t(st.st_size), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  ASSERT_NE(memory, MAP_FAILED);
  // The claim is the last 8 bytes of the object (trephine_bridge_shm.c's
  // layout): the pid above, the low 32 bits of its start time below.
  auto* claim = reinterpret_cast<std::atomic<uint64_t>*>(static_cast<char*>(memory) + st.st_size - 8);
  ASSERT_EQ(claim->load() >> 32, static_cast<uint64_t>(parent));
  claim->store(claim->load() ^ 0x5a5a);
  EXPECT_EQ(trephine_bridge_shm_claim(shm, static_cast<long>(getpid())), 0) << "a reused pid does not hold it";
  munmap(memory, size_t(st.st_size));
  close(fd);
  trephine_bridge_shm_close(shm, name.c_str(), 1);
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
