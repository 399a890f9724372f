#include "plugins/openigtlink/IgtlServer.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <signal.h>
#include <time.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>

#include "plugins/openigtlink/IgtlStreamReader.h"
#include "plugins/openigtlink/ListeningSocket.h"

namespace trephine::openigtlink {

namespace {

constexpr uint64_t kSlowClientNs = 1'000'000'000;  // a full send buffer for this long: disconnected

// How often the network thread looks for forces the haptic loop posted: a
// force reaches the clients within this (and the socket's) delay.
constexpr uint64_t kForcePollNs = 200'000;

}  // namespace

struct IgtlServer::Client {
  int fd = -1;
  std::unique_ptr<IgtlStreamReader> reader;
  uint64_t blockedSinceNs = 0;  // 0: its last send went through
  sockaddr_in address{};
  uint64_t acceptedNs = 0, lastByteNs = 0;
  bool sentMessage = false;  // a message of it was taken (a pose or buttons of the device's client)
};

namespace {

// "HOST" or "HOST:PORT" against a client's address.
bool addressMatches(const std::string& wanted, const sockaddr_in& address) {
  char host[INET_ADDRSTRLEN] = {};
  inet_ntop(AF_INET, &address.sin_addr, host, sizeof host);
  const std::string port = std::to_string(ntohs(address.sin_port));
  return wanted == host || wanted == std::string(host) + ":" + port;
}

}  // namespace

IgtlServer::IgtlServer(IgtlServerOptions options) : m_options(std::move(options)) {
  const Listener listener = listenOn(m_options.host, m_options.port);
  m_listener = listener.fd;
  m_port = listener.port;
  m_wake = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (m_wake < 0) {
    close(m_listener);
    throw std::runtime_error("cannot make an eventfd: " + std::string(std::strerror(errno)));
  }
  m_clients.reserve(m_options.maxClients);
  m_thread = std::thread([this] { run(); });
}

IgtlServer::~IgtlServer() {
  stop();
  close(m_wake);
}

void IgtlServer::stop() {
  if (!m_thread.joinable()) return;
  m_stop = true;
  const uint64_t one = 1;
  [[maybe_unused]] const ssize_t written = write(m_wake, &one, sizeof one);
  m_thread.join();
  for (auto& c : m_clients) close(c->fd);
  m_clients.clear();
  m_clientCount = 0;
  close(m_listener);
  m_listener = -1;
}

void IgtlServer::postForce(const Vec3& force_N, double t) {
  // Only the ring: waking the network thread (an eventfd write) cost the
  // haptic frame 20 µs on a virtual machine (docs/results.md). The thread
  // looks at the ring every kForcePollNs instead.
  m_forces.push({force_N, t});
}

void IgtlServer::run() {
  std::vector<pollfd> fds;
  fds.reserve(2 + m_options.maxClients);
  while (!m_stop.load(std::memory_order_relaxed)) {
    fds.clear();
    fds.push_back({m_listener, POLLIN, 0});
    fds.push_back({m_wake, POLLIN, 0});
    for (const auto& c : m_clients) fds.push_back({c->fd, POLLIN, 0});
    const timespec wait{0, static_cast<long>(kForcePollNs)};
    if (ppoll(fds.data(), fds.size(), &wait, nullptr) < 0 && errno != EINTR) break;
    if (fds[1].revents & POLLIN) {
      uint64_t count;
      [[maybe_unused]] const ssize_t got = read(m_wake, &count, sizeof count);
    }
    // Clients first (their fds are in the same order as m_clients), then forces, then new clients.
    for (size_t i = 0; i < m_clients.size(); ++i)
      if (fds[2 + i].revents & (POLLIN | POLLHUP | POLLERR)) readClient(*m_clients[i]);
    dropStalledClients(steadyNs());
    sendForces();
    std::erase_if(m_clients, [&](const std::unique_ptr<Client>& c) {
      if (c->fd >= 0) return false;
      return true;
    });
    m_clientCount.store(m_clients.size(), std::memory_order_relaxed);
    if (fds[0].revents & POLLIN) acceptClients();
  }
}

void IgtlServer::disconnect(Client& client) {
  if (client.fd >= 0) close(client.fd);
  client.fd = -1;
  if (m_poseSource == &client) m_poseSource = nullptr;  // the next client with a pose takes over
}

void IgtlServer::dropStalledClients(uint64_t now) {
  for (auto& c : m_clients)
    if (c->fd >= 0 && c->reader->midMessage() && now - c->lastByteNs > timeoutNs()) {
      ++m_counters.clientsStalled;
      disconnect(*c);
    }
}

bool IgtlServer::isPoseSource(const Client& client) {
  if (!m_options.client.empty()) return addressMatches(m_options.client, client.address);
  if (!m_poseSource) m_poseSource = &client;
  return m_poseSource == &client;
}

void IgtlServer::acceptClients() {
  for (;;) {
    sockaddr_in address{};
    socklen_t length = sizeof address;
    const int fd = accept4(m_listener, reinterpret_cast<sockaddr*>(&address), &length, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;
    const uint64_t now = steadyNs();
    if (m_clients.size() >= m_options.maxClients) {
      // Room is made by a client that has held its connection without
      // sending a message (a connection left open, or one that only holds a slot).
      Client* idle = nullptr;
      for (auto& c : m_clients)
        if (c->fd >= 0 && !c->sentMessage && now - c->acceptedNs > timeoutNs() && c.get() != m_poseSource)
          idle = c.get();
      if (!idle) {
        ++m_counters.clientsRefused;
        close(fd);
        continue;
      }
      ++m_counters.clientsIdle;
      disconnect(*idle);
      std::erase_if(m_clients, [](const std::unique_ptr<Client>& c) { return c->fd < 0; });
    }
    const int yes = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);  // a force is 92 bytes: send each at once
    auto client = std::make_unique<Client>();
    client->fd = fd;
    client->address = address;
    client->acceptedNs = client->lastByteNs = now;
    Client* self = client.get();
    client->reader = std::make_unique<IgtlStreamReader>(
        [this](const MessageHeader& h) {
          const bool transform = h.typeName() == "TRANSFORM" && h.deviceName() == m_options.transformName;
          const bool buttons = !m_options.buttonsName.empty() && h.deviceName() == m_options.buttonsName &&
                               (h.typeName() == "STRING" || h.typeName() == "STATUS");
          if (!transform && !buttons) ++m_counters.otherMessages;
          return transform || buttons;
        },
        [this, self](const MessageHeader& h, std::span<const unsigned char> content) {
          if (h.typeName() == "TRANSFORM") {
            const auto transform = decodeTransform(content);
            if (!transform) {
              ++m_counters.badTransforms;
              return;
            }
            // Judged before its client may become the device's: a pose
            // beyond the workspace never is the hand's place.
            if (!(transform->translation.norm() <= m_options.workspace)) {
              ++m_counters.posesOutsideWorkspace;
              return;
            }
            if (!isPoseSource(*self)) {
              ++m_counters.posesOtherClients;
              return;
            }
            self->sentMessage = true;  // a message taken: not a client that only holds its connection
            ReceivedPose& pose = m_poses.writeSlot();
            pose.sequence = ++m_poseSequence;
            pose.transform = *transform;
            pose.buttons = m_buttons;
            m_poses.publish();
            ++m_counters.transforms;
            return;
          }
          // Buttons: a STRING holding the mask as a number, or a STATUS's
          // subcode; from the device's client only.
          if (m_poseSource != self && !(m_options.client.size() && addressMatches(m_options.client, self->address))) {
            ++m_counters.posesOtherClients;
            return;
          }
          self->sentMessage = true;
          if (h.typeName() == "STRING") {
            const auto text = decodeString(content);
            if (!text) return;
            uint32_t mask = 0;
            for (const char c : *text) {
              if (c < '0' || c > '9') return;
              mask = mask * 10 + static_cast<uint32_t>(c - '0');
            }
            m_buttons = mask;
          } else if (const auto subcode = decodeStatusSubcode(content)) {
            m_buttons = static_cast<uint32_t>(*subcode);
          }
          ++m_counters.buttonMessages;
        });
    m_clients.push_back(std::move(client));
    ++m_counters.clientsAccepted;
  }
}

void IgtlServer::readClient(Client& client) {
  unsigned char buffer[16384];
  for (;;) {
    const ssize_t got = recv(client.fd, buffer, sizeof buffer, MSG_DONTWAIT);
    if (got > 0) {
      client.lastByteNs = steadyNs();
      if (!client.reader->feed({buffer, static_cast<size_t>(got)})) {
        ++m_counters.clientsBroken;
        disconnect(client);
        return;
      }
      continue;
    }
    if (got == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) disconnect(client);  // gone
    return;
  }
}

void IgtlServer::sendForces() {
  std::array<unsigned char, kForceSensorMessageSize> message{};
  m_forces.drain([&](const PostedForce& f) {
    encodeForceSensor(m_options.forceName, toTimestamp(f.t), f.force, message);
    for (auto& c : m_clients) {
      if (c->fd < 0) continue;
      const ssize_t sent = send(c->fd, message.data(), message.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
      if (sent == static_cast<ssize_t>(message.size())) {
        ++m_counters.sensorsSent;
        c->blockedSinceNs = 0;
        continue;
      }
      if (sent > 0 || (sent < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) {
        // Part of a message went (the stream is now cut mid-message), or the socket failed: let it go.
        ++m_counters.clientsSlow;
        disconnect(*c);
        continue;
      }
      ++m_counters.sensorsDropped;
      const uint64_t now = steadyNs();
      if (c->blockedSinceNs == 0) c->blockedSinceNs = now;
      if (now - c->blockedSinceNs > kSlowClientNs) {
        ++m_counters.clientsSlow;
        disconnect(*c);
      }
    }
  });
}

}  // namespace trephine::openigtlink
