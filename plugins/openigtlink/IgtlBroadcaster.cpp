#include "plugins/openigtlink/IgtlBroadcaster.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "plugins/openigtlink/ListeningSocket.h"

namespace trephine::openigtlink {

IgtlBroadcaster::IgtlBroadcaster(const std::string& host, uint16_t port, size_t maxClients, size_t maxQueued,
                                 double clientTimeoutS)
    : m_maxClients(maxClients), m_maxQueued(maxQueued), m_timeoutNs(static_cast<uint64_t>(clientTimeoutS * 1e9)) {
  const Listener listener = listenOn(host, port);
  m_listener = listener.fd;
  m_port = listener.port;
}

IgtlBroadcaster::~IgtlBroadcaster() {
  for (auto& c : m_clients) close(*c);
  ::close(m_listener);
}

void IgtlBroadcaster::close(Client& client) {
  if (client.fd >= 0) ::close(client.fd);
  client.fd = -1;
  client.queue.clear();
  client.queuedBytes = 0;
}

size_t IgtlBroadcaster::poll() {
  for (auto& c : m_clients) c->fresh = false;
  m_new.clear();
  size_t fresh = 0;
  for (;;) {
    const int fd = accept4(m_listener, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) break;
    if (m_clients.size() >= m_maxClients) {
      // Room is made by the client behind the longest, if it has been behind
      // a fifth of the timeout (a second by default): it is not keeping up.
      const uint64_t now = steadyNs();
      Client* slowest = nullptr;
      for (auto& c : m_clients)
        if (c->fd >= 0 && c->behindSinceNs && now - c->behindSinceNs > m_timeoutNs / 5 &&
            (!slowest || c->behindSinceNs < slowest->behindSinceNs))
          slowest = c.get();
      if (!slowest) {
        ++m_refused;
        ::close(fd);
        continue;
      }
      ++m_dropped;
      close(*slowest);
      std::erase_if(m_clients, [](const std::unique_ptr<Client>& c) { return c->fd < 0; });
    }
    const int yes = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
    auto client = std::make_unique<Client>();
    client->fd = fd;
    client->fresh = true;
    client->id = m_nextId++;
    m_new.push_back(client->id);
    m_clients.push_back(std::move(client));
    ++m_accepted;
    ++fresh;
  }
  unsigned char sink[4096];
  for (auto& c : m_clients) {
    // What a client sends (a viewer's queries) is read and let go; end of stream: it left.
    for (;;) {
      const ssize_t got = recv(c->fd, sink, sizeof sink, MSG_DONTWAIT);
      if (got > 0) continue;
      if (got == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) close(*c);
      break;
    }
    if (c->fd >= 0) flush(*c);
  }
  std::erase_if(m_clients, [](const std::unique_ptr<Client>& c) { return c->fd < 0; });
  return fresh;
}

void IgtlBroadcaster::queue(Client& c, std::shared_ptr<const std::vector<unsigned char>> message) {
  if (c.fd < 0) return;
  c.queuedBytes += message->size();
  c.queue.push_back(std::move(message));
  if (c.queuedBytes > m_maxQueued) {
    ++m_dropped;
    close(c);
    return;
  }
  flush(c);
}

void IgtlBroadcaster::broadcast(std::shared_ptr<const std::vector<unsigned char>> message) {
  for (auto& c : m_clients) queue(*c, message);
}

void IgtlBroadcaster::sendToNew(std::shared_ptr<const std::vector<unsigned char>> message) {
  for (auto& c : m_clients)
    if (c->fresh) queue(*c, message);
}

bool IgtlBroadcaster::sendTo(uint64_t id, std::shared_ptr<const std::vector<unsigned char>> message) {
  for (auto& c : m_clients)
    if (c->id == id && c->fd >= 0) {
      queue(*c, std::move(message));
      return c->fd >= 0;
    }
  return false;
}

std::optional<size_t> IgtlBroadcaster::queued(uint64_t id) const {
  for (const auto& c : m_clients)
    if (c->id == id && c->fd >= 0) return c->queuedBytes - c->sentOfFront;
  return std::nullopt;
}

void IgtlBroadcaster::flush(Client& c) {
  bool progressed = false;
  while (c.fd >= 0 && !c.queue.empty()) {
    const auto& front = *c.queue.front();
    const ssize_t sent = send(c.fd, front.data() + c.sentOfFront, front.size() - c.sentOfFront,
                              MSG_DONTWAIT | MSG_NOSIGNAL);
    if (sent < 0) {
      if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) close(c);
      break;
    }
    c.sentOfFront += static_cast<size_t>(sent);
    progressed |= sent > 0;
    if (c.sentOfFront < front.size()) break;  // the socket is full: the rest at the next poll
    c.queuedBytes -= front.size();
    c.queue.pop_front();
    c.sentOfFront = 0;
    ++m_sent;
  }
  if (c.fd < 0) return;
  // Behind since when (for making room), and taking nothing since when: a
  // client that takes nothing of its queue for the timeout is let go, one
  // that reads slowly keeps its connection until room is needed.
  if (c.queue.empty()) {
    c.behindSinceNs = c.stalledSinceNs = 0;
    return;
  }
  const uint64_t now = steadyNs();
  if (c.behindSinceNs == 0) c.behindSinceNs = now;
  if (progressed) c.stalledSinceNs = 0;
  else if (c.stalledSinceNs == 0) c.stalledSinceNs = now;
  if (c.stalledSinceNs && now - c.stalledSinceNs > m_timeoutNs) {
    ++m_dropped;
    close(c);
  }
}

}  // namespace trephine::openigtlink
