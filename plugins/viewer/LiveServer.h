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
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

namespace trephine::viewer {

class LiveServer {
 public:
  // Listens on `port` (0: any free port). Throws std::runtime_error when it
  // cannot (the port taken, say), saying so.
  LiveServer(int port, std::filesystem::path assets, std::string manifest);
  ~LiveServer();
  LiveServer(const LiveServer&) = delete;
  LiveServer& operator=(const LiveServer&) = delete;

  int port() const;
  void send(const std::string& key, std::string bytes, bool binary);
  uint64_t clients() const;    // connections to /stream so far
  uint64_t coalesced() const;  // messages a slow client skipped (a newer one of the same key went instead)

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace trephine::viewer
