#pragma once
// A server that streams messages to every client that connects (3D Slicer's
// OpenIGTLinkIF, a PLUS or a script), polled by its owner's thread: poll()
// accepts new clients, drains and ignores what they send (a viewer's
// queries), and sends what is queued without waiting. Each client has its
// own queue, so a message reaches it whole however the socket takes it; a
// client whose queue passes `maxQueued` bytes, or that has taken nothing of
// it for `clientTimeout` (it does not read), is disconnected, the others go
// on; with every connection taken, the client behind the longest (its queue
// not emptied) makes room for a new one. Binds 127.0.0.1 unless asked.
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace trephine::openigtlink {

class IgtlBroadcaster {
 public:
  // Throws std::runtime_error naming host:port and the reason.
  IgtlBroadcaster(const std::string& host, uint16_t port, size_t maxClients, size_t maxQueued,
                  double clientTimeoutS = 5.0);
  ~IgtlBroadcaster();
  IgtlBroadcaster(const IgtlBroadcaster&) = delete;
  IgtlBroadcaster& operator=(const IgtlBroadcaster&) = delete;

  uint16_t port() const { return m_port; }
  // Accepts, reads and sends what it can now. Returns how many clients are
  // new since the last call (the owner sends them what they missed).
  size_t poll();
  // Queues a message for every client (shared: queued once in memory).
  void broadcast(std::shared_ptr<const std::vector<unsigned char>> message);
  // Queues a message for the clients accepted at the last poll() only.
  void sendToNew(std::shared_ptr<const std::vector<unsigned char>> message);
  // The clients accepted at the last poll(), by id; a message for one of them.
  const std::vector<uint64_t>& newClients() const { return m_new; }
  // Queues a message for client `id`; false when it is gone.
  bool sendTo(uint64_t id, std::shared_ptr<const std::vector<unsigned char>> message);
  // Bytes queued for client `id` and not yet sent; nothing when it is gone.
  std::optional<size_t> queued(uint64_t id) const;
  size_t clients() const { return m_clients.size(); }

  uint64_t accepted() const { return m_accepted; }
  uint64_t refused() const { return m_refused; }
  uint64_t dropped() const { return m_dropped; }  // disconnected for not reading (or too slowly)
  uint64_t messagesSent() const { return m_sent; }

 private:
  struct Client {
    int fd = -1;
    std::deque<std::shared_ptr<const std::vector<unsigned char>>> queue;
    size_t sentOfFront = 0;  // bytes of the first message already sent
    size_t queuedBytes = 0;
    bool fresh = false;
    uint64_t id = 0;
    uint64_t behindSinceNs = 0;   // its queue has not been empty since (0: it is)
    uint64_t stalledSinceNs = 0;  // nothing of its queue was taken since (0: it is taking it)
  };
  void flush(Client& client);
  void queue(Client& client, std::shared_ptr<const std::vector<unsigned char>> message);
  void close(Client& client);

  int m_listener = -1;
  uint16_t m_port = 0;
  size_t m_maxClients, m_maxQueued;
  uint64_t m_timeoutNs;
  uint64_t m_nextId = 1;
  std::vector<uint64_t> m_new;
  std::vector<std::unique_ptr<Client>> m_clients;
  uint64_t m_accepted = 0, m_refused = 0, m_dropped = 0, m_sent = 0;
};

}  // namespace trephine::openigtlink
