#pragma once
// The OpenIGTLink server behind IGTLinkDevice: a thread of its own that
// listens on host:port (127.0.0.1 unless asked), accepts up to `maxClients`
// connections, reads each client's TRANSFORM (and button) messages and hands
// the newest pose to the haptic loop through a triple buffer, and sends every
// client each force the haptic loop posts, as a SENSOR. The haptic loop only
// fetches and pushes to a ring, which the network thread looks at every
// 200 µs: it never waits on the network, nor wakes a thread. A client that breaks the protocol, or does not read its forces
// until its socket's buffer is full for a second, is disconnected; the others
// go on. Counters are atomics any thread may read.
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "framework/channels/ChangeQueue.h"
#include "framework/channels/TripleBuffer.h"
#include "framework/math/Math.h"
#include "plugins/openigtlink/IgtlMessages.h"

namespace trephine::openigtlink {

struct IgtlServerOptions {
  std::string host = "127.0.0.1";
  uint16_t port = 18944;  // 0: any free port
  size_t maxClients = 4;
  std::string transformName = "Tool";
  std::string forceName = "Force";
  std::string buttonsName;  // "" for none
  // Whose poses drive the device: "" the first client whose pose is taken
  // (until it leaves), or "HOST" / "HOST:PORT" of the one client to hear.
  std::string client;
  // A pose farther than this from the origin (mm) is never taken: a stray
  // first pose cannot become the hand's place.
  double workspace = 1000;
  // s: a client stopped mid-message this long is let go; one that sent no
  // message since it came this long ago makes room when all are taken.
  double clientTimeout = 5;
};

struct ReceivedPose {
  uint64_t sequence = 0;  // 0: none yet
  Transform transform;
  uint32_t buttons = 0;
};

struct ServerCounters {
  std::atomic<uint64_t> transforms{0};      // poses taken
  std::atomic<uint64_t> badTransforms{0};   // TRANSFORM bodies that are not a rigid transform
  std::atomic<uint64_t> buttonMessages{0};  // STRING/STATUS taken as buttons
  std::atomic<uint64_t> otherMessages{0};   // messages of other types or names, skipped
  std::atomic<uint64_t> clientsAccepted{0};
  std::atomic<uint64_t> clientsRefused{0};  // over maxClients
  std::atomic<uint64_t> clientsBroken{0};   // disconnected for breaking the protocol
  std::atomic<uint64_t> clientsSlow{0};     // disconnected for not reading
  std::atomic<uint64_t> clientsStalled{0};  // disconnected for stopping mid-message
  std::atomic<uint64_t> clientsIdle{0};     // disconnected to make room: connected, never sent a message
  std::atomic<uint64_t> posesOtherClients{0};     // TRANSFORMs of a client that is not the device's, ignored
  std::atomic<uint64_t> posesOutsideWorkspace{0};  // TRANSFORMs farther than the workspace, ignored
  std::atomic<uint64_t> sensorsSent{0};     // SENSOR messages, summed over clients
  std::atomic<uint64_t> sensorsDropped{0};  // not sent: the client's buffer was full
};

class IgtlServer {
 public:
  // Binds and listens; throws std::runtime_error naming the address and the reason.
  explicit IgtlServer(IgtlServerOptions options);
  ~IgtlServer();
  IgtlServer(const IgtlServer&) = delete;
  IgtlServer& operator=(const IgtlServer&) = delete;

  uint16_t port() const { return m_port; }
  // Stops serving: the thread ends and every socket closes; the counters stay.
  void stop();
  // The haptic loop's side: the newest pose (fetch, then read).
  TripleBuffer<ReceivedPose>& poses() { return m_poses; }
  // The haptic loop's side: this frame's force (N) at time t (s). Never waits, never wakes a thread.
  void postForce(const Vec3& force_N, double t);
  const ServerCounters& counters() const { return m_counters; }
  // Forces the ring could not hold (the network thread fell behind).
  uint64_t forcesDropped() const { return m_forces.dropped(); }
  // Clients connected now.
  size_t clients() const { return m_clientCount.load(std::memory_order_relaxed); }

 private:
  struct Client;
  struct PostedForce {
    Vec3 force = Vec3::Zero();
    double t = 0;
  };
  void run();
  void acceptClients();
  void readClient(Client& client);
  // Whether `client` is the one whose poses the device takes (making it so
  // when none is and it may be).
  bool isPoseSource(const Client& client);
  void dropStalledClients(uint64_t now);
  void disconnect(Client& client);
  uint64_t timeoutNs() const { return static_cast<uint64_t>(m_options.clientTimeout * 1e9); }
  void sendForces();

  IgtlServerOptions m_options;
  int m_listener = -1;
  int m_wake = -1;  // eventfd: stop
  uint16_t m_port = 0;
  std::atomic<bool> m_stop{false};
  TripleBuffer<ReceivedPose> m_poses;
  ChangeQueue<PostedForce> m_forces{4096};
  ServerCounters m_counters;
  std::atomic<size_t> m_clientCount{0};
  std::vector<std::unique_ptr<Client>> m_clients;  // the network thread's
  uint64_t m_poseSequence = 0;
  const Client* m_poseSource = nullptr;  // the client whose poses are taken; null: none yet
  uint32_t m_buttons = 0;
  std::thread m_thread;
};

}  // namespace trephine::openigtlink
