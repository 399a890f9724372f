#pragma once
// The far end of a device bridge for tests, written on the C code alone (as
// a device program or a simulation outside the process would be): a thread
// that, every millisecond, sends a packet and records what came back.
#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "trephine_bridge.h"
#include "trephine_bridge_shm.h"
#include "trephine_bridge_udp.h"

namespace trephine::test {

uint64_t monotonicNowNs();
// A UDP port that was free a moment ago (bound and released).
uint16_t freeUdpPort();

// Where packets go: one shared memory object, or UDP to a port on 127.0.0.1.
struct PeerLink {
  std::string channel;          // shm when not empty
  uint16_t simulationPort = 0;  // UDP otherwise: the simulation's port

  // A shared memory object of its own, named for `what` and this process.
  static PeerLink sharedMemory(const std::string& what);
  // UDP to a port that was free a moment ago.
  static PeerLink udp();
  // The BridgeDevice attributes that open this link (channel, or transport and address).
  std::string attributes() const;
};

// A device program: sends the pose `poseAt(t)` (t: s since start) each
// millisecond while `sending(t)`, and records every force it receives.
class FakeDevice {
 public:
  struct ReceivedForce {
    uint64_t atNs = 0;  // when it came (monotonic)
    trephine_bridge_force force{};
  };
  using PoseAt = std::function<trephine_bridge_pose(double t)>;
  using Sending = std::function<bool(double t)>;

  FakeDevice(
      PeerLink link, PoseAt poseAt, Sending sending = [](double) { return true; });
  ~FakeDevice();
  void start();
  // Stops the thread and returns everything received.
  std::vector<ReceivedForce> stop();
  uint64_t startNs() const { return m_startNs; }
  // Sends raw bytes from the device's own socket (UDP) as they are.
  void sendRaw(const unsigned char* bytes, size_t size);
  // The sending times (monotonic ns) by pose sequence, for round trips.
  std::vector<uint64_t> sentAt() const;
  // As a device program started again: a new session, its sequence from 1.
  void restart() { m_restart = true; }
  // A device that takes no force (its poses never say it heard one), as a
  // device program that counts every force stale would.
  void ignoreForces(bool ignore) { m_ignoreForces = ignore; }
  uint64_t session() const { return m_session; }

 private:
  void run();
  PeerLink m_link;
  PoseAt m_poseAt;
  Sending m_sending;
  trephine_bridge_shm* m_shm = nullptr;
  trephine_bridge_udp* m_udp = nullptr;
  trephine_bridge_address m_simulation{};
  std::atomic<bool> m_stop{false};
  std::atomic<bool> m_restart{false}, m_ignoreForces{false};
  std::atomic<uint64_t> m_session{trephine_bridge_new_session()};
  std::thread m_thread;
  uint64_t m_startNs = 0;
  mutable std::mutex m_mutex;  // the test thread's raw sends beside the device thread's
  std::vector<ReceivedForce> m_received;
  std::vector<uint64_t> m_sentAt;
};

}  // namespace trephine::test
