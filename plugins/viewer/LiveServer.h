#pragma once
// The live view's server (`trephine run --realtime --view PORT`): on
// 127.0.0.1, it serves the browser viewer (index.html and viewer.js from the
// built assets, and a manifest that puts the viewer in live mode) and a
// WebSocket at /stream that every message sent goes to. Each message has a
// key: a client that falls behind gets only the latest message of each key
// (the tool's pose, the brain's positions, a skull block's surface), so
// nothing queues up without bound, and a client that connects late first
// gets the latest message of every key, in the order the keys first came.
// Boost.Beast stays inside LiveServer.cpp; the server has a thread of its
// own, and send() only takes a lock and posts to it (from the exporter's
// group, never from the haptic thread).
//
// It answers only its own pages (LiveOrigin.h): a request whose Host is not
// this server by a loopback name, or a WebSocket upgrade from a page of
// another origin, gets 403. It survives misbehaving clients within Limits:
// a bounded number of connections (the rest are closed at once, so the
// server never takes the descriptors the exporter writes its files with),
// requests that must arrive whole in time, WebSocket clients that must keep
// reading, and accept() failures that only pause accepting.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

namespace trephine::viewer {

class LiveServer {
 public:
  struct Limits {
    // Connections open at once (HTTP and WebSocket); one more is closed as
    // soon as it is accepted. Each costs one file descriptor.
    int maxConnections = 16;
    // An HTTP request must arrive whole, and its answer be taken, within this.
    std::chrono::milliseconds requestTimeout{5000};
    // A WebSocket client that neither reads what is sent nor answers a ping
    // for this long is closed (a ping goes out after half of it).
    std::chrono::milliseconds streamIdleTimeout{20000};
    // A message sent to a WebSocket client must be taken whole within this:
    // a client that reads too slowly to (while answering pings) is closed,
    // so slow clients never hold the connections for good.
    std::chrono::milliseconds writeTimeout{10000};
    // After accept() fails (no descriptor left, say), accepting resumes after this.
    std::chrono::milliseconds acceptRetry{100};
  };

  // Listens on 127.0.0.1:`port` (0: any free port). Throws std::runtime_error
  // when it cannot (the port taken, say), saying so.
  LiveServer(int port, std::filesystem::path assets, std::string manifest, Limits limits);
  LiveServer(int port, std::filesystem::path assets, std::string manifest)
      : LiveServer(port, std::move(assets), std::move(manifest), Limits{}) {}
  ~LiveServer();
  LiveServer(const LiveServer&) = delete;
  LiveServer& operator=(const LiveServer&) = delete;

  int port() const;
  void send(const std::string& key, std::string bytes, bool binary);
  uint64_t clients() const;    // connections to /stream so far
  uint64_t coalesced() const;  // messages a slow client skipped (a newer one of the same key went instead)
  uint64_t refused() const;    // requests answered 403: a foreign Host or Origin
  uint64_t overLimit() const;  // connections closed at once: maxConnections were open
  uint64_t timedOut() const;   // connections closed for a request too slow or a client not reading
  uint64_t acceptErrors() const;  // accept() failures (each followed by a pause of acceptRetry)
  int openConnections() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace trephine::viewer
