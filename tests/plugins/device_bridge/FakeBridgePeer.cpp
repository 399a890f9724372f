#include "FakeBridgePeer.h"

#include <gtest/gtest.h>
#include <time.h>
#include <unistd.h>

#include <chrono>
#include <cstring>

namespace trephine::test {

uint64_t monotonicNowNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1000000000ull + static_cast<uint64_t>(ts.tv_nsec);
}

uint16_t freeUdpPort() {
  trephine_bridge_address any{};
  trephine_bridge_address_parse("127.0.0.1", 0, &any);
  int error = 0;
  trephine_bridge_udp* udp = trephine_bridge_udp_open(&any, &error);
  EXPECT_NE(udp, nullptr) << std::strerror(error);
  if (!udp) return 0;
  const uint16_t port = trephine_bridge_udp_local(udp).port;
  trephine_bridge_udp_close(udp);
  return port;
}

PeerLink PeerLink::sharedMemory(const std::string& what) {
  static std::atomic<int> count{0};
  return {"/trephine-test-" + what + "-" + std::to_string(getpid()) + "-" + std::to_string(++count), 0};
}

PeerLink PeerLink::udp() { return {"", freeUdpPort()}; }

std::string PeerLink::attributes() const {
  if (!channel.empty()) return "channel=\"" + channel + "\"";
  return "transport=\"udp\" address=\"127.0.0.1:" + std::to_string(simulationPort) + "\"";
}

FakeDevice::FakeDevice(PeerLink link, PoseAt poseAt, Sending sending)
    : m_link(std::move(link)), m_poseAt(std::move(poseAt)), m_sending(std::move(sending)) {
  int error = 0;
  if (!m_link.channel.empty()) {
    m_shm = trephine_bridge_shm_open(m_link.channel.c_str(), 1, &error);
    EXPECT_NE(m_shm, nullptr) << std::strerror(error);
    // A test may truncate the object under both sides: this one survives it too.
    if (m_shm) trephine_bridge_shm_guard_truncation(m_shm);
  } else {
    trephine_bridge_address local{};
    trephine_bridge_address_parse("127.0.0.1", 0, &local);
    m_udp = trephine_bridge_udp_open(&local, &error);
    EXPECT_NE(m_udp, nullptr) << std::strerror(error);
    trephine_bridge_address_parse("127.0.0.1", m_link.simulationPort, &m_simulation);
  }
  m_received.reserve(100000);
  m_sentAt.reserve(100000);
}

FakeDevice::~FakeDevice() {
  stop();
  if (m_shm) trephine_bridge_shm_close(m_shm, m_link.channel.c_str(), 1);
  if (m_udp) trephine_bridge_udp_close(m_udp);
}

void FakeDevice::start() {
  m_startNs = monotonicNowNs();
  m_thread = std::thread([this] { run(); });
}

std::vector<FakeDevice::ReceivedForce> FakeDevice::stop() {
  m_stop = true;
  if (m_thread.joinable()) m_thread.join();
  std::lock_guard lock(m_mutex);
  return m_received;
}

std::vector<uint64_t> FakeDevice::sentAt() const {
  std::lock_guard lock(m_mutex);
  return m_sentAt;
}

void FakeDevice::sendRaw(const unsigned char* bytes, size_t size) {
  std::lock_guard lock(m_mutex);
  if (m_udp) trephine_bridge_udp_send(m_udp, &m_simulation, bytes, size);
}

void FakeDevice::run() {
  uint64_t next = m_startNs;
  uint64_t sequence = 0, lastForceWrites = m_shm ? trephine_bridge_shm_force_writes(m_shm) : 0;
  trephine_bridge_force heard{};  // the last force taken: its session and sequence go back in each pose
  while (!m_stop) {
    const uint64_t now = monotonicNowNs();
    if (m_restart.exchange(false)) {
      m_session = trephine_bridge_new_session();
      sequence = 0;
      heard = {};
    }
    // Forces, as they come.
    unsigned char bytes[128];
    trephine_bridge_force force{};
    if (m_shm) {
      const uint64_t writes = trephine_bridge_shm_force_writes(m_shm);
      if (writes != lastForceWrites && trephine_bridge_shm_read_force(m_shm, bytes) &&
          trephine_bridge_decode_force(bytes, TREPHINE_BRIDGE_FORCE_SIZE, &force) == TREPHINE_BRIDGE_OK) {
        lastForceWrites = writes;
        if (!m_ignoreForces) heard = force;
        std::lock_guard lock(m_mutex);
        m_received.push_back({now, force});
      }
    } else {
      trephine_bridge_address from{};
      long size;
      while ((size = trephine_bridge_udp_receive(m_udp, bytes, sizeof bytes, &from)) >= 0)
        if (trephine_bridge_decode_force(bytes, static_cast<size_t>(size), &force) == TREPHINE_BRIDGE_OK) {
          if (!m_ignoreForces) heard = force;
          std::lock_guard lock(m_mutex);
          m_received.push_back({monotonicNowNs(), force});
        }
    }
    if (now >= next) {
      const double t = static_cast<double>(now - m_startNs) * 1e-9;
      next += 1000000;
      if (m_sending(t)) {
        trephine_bridge_pose pose = m_poseAt(t);
        pose.sequence = ++sequence;
        pose.device_time_ns = now;
        pose.session = m_session;
        pose.heard_session = heard.session;
        pose.heard_sequence = heard.sequence;
        if (trephine_bridge_encode_pose(&pose, bytes) == TREPHINE_BRIDGE_OK) {
          std::lock_guard lock(m_mutex);
          m_sentAt.push_back(now);
          if (m_shm) {
            trephine_bridge_shm_write_pose(m_shm, bytes);
          } else {
            trephine_bridge_udp_send(m_udp, &m_simulation, bytes, TREPHINE_BRIDGE_POSE_SIZE);
          }
        }
      }
    }
    std::this_thread::sleep_for(std::chrono::microseconds(20));
  }
}

}  // namespace trephine::test
