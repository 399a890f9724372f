#include "plugins/viewer/LiveServer.h"

#include <atomic>
#include <utility>  // before Asio: Boost 1.74's awaitable.hpp uses std::exchange without it

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/address.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <deque>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <sstream>
#include <thread>
#include <vector>

#include "plugins/viewer/LiveOrigin.h"

namespace trephine::viewer {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

namespace {

struct Message {
  std::string bytes;
  bool binary = false;
};
using MessagePtr = std::shared_ptr<const Message>;

// Boost 1.74's Beast has a string_view of its own.
std::string_view standard(beast::string_view text) { return {text.data(), text.size()}; }

std::string contentType(const std::string& file) {
  if (file.ends_with(".html")) return "text/html; charset=utf-8";
  if (file.ends_with(".js")) return "text/javascript; charset=utf-8";
  return "application/octet-stream";
}

}  // namespace

// Handlers hold the server by plain pointer: it outlives its thread (the
// destructor joins it), and a handler holding it by shared pointer in its own
// io_context would keep both alive forever.
struct LiveServer::Impl {
  class Stream;
  class Request;

  // Declared before the io_context: connections still queued in it when it
  // is destroyed give their slots back here.
  Limits limits;
  std::atomic<int> open{0};
  std::atomic<uint64_t> clientCount{0}, coalescedCount{0}, refusedCount{0}, overLimitCount{0}, timedOutCount{0},
      acceptErrorCount{0};

  asio::io_context io;
  tcp::acceptor acceptor{io};
  asio::steady_timer acceptPause{io};
  std::thread thread;
  std::filesystem::path assets;
  std::string manifest;
  int port = 0;
  // The latest message of each key, in the order the keys first came; the
  // lock is shared with send().
  std::mutex keptLock;
  std::vector<std::pair<std::string, MessagePtr>> kept;
  std::map<std::string, size_t> keptIndex;
  std::set<std::shared_ptr<Stream>> streams;  // the io thread's only

  // One of the `limits.maxConnections` a connection holds while open.
  class Slot {
   public:
    explicit Slot(std::atomic<int>& open) : m_open(&open) { ++*m_open; }
    Slot(Slot&& other) noexcept : m_open(std::exchange(other.m_open, nullptr)) {}
    Slot& operator=(Slot&&) = delete;
    ~Slot() {
      if (m_open) --*m_open;
    }

   private:
    std::atomic<int>* m_open;
  };

  // One WebSocket client: its keys waiting to be written (each once, with its
  // latest message).
  class Stream : public std::enable_shared_from_this<Stream> {
   public:
    Stream(beast::tcp_stream stream, Impl& server, Slot slot)
        : m_ws(std::move(stream)), m_server(server), m_slot(std::move(slot)), m_writeDeadline(m_ws.get_executor()) {}

    void start(http::request<http::string_body> request) {
      // A client must answer the pings that go out after half the idle time,
      // which it cannot do while it does not read what is sent: either way
      // it is closed, and its pending write with it.
      websocket::stream_base::timeout timeout{};
      timeout.handshake_timeout = m_server.limits.requestTimeout;
      timeout.idle_timeout = m_server.limits.streamIdleTimeout;
      timeout.keep_alive_pings = true;
      m_ws.set_option(timeout);
      m_ws.read_message_max(kIncomingMessageLimit);
      m_ws.binary(true);
      m_ws.auto_fragment(false);  // a message is one frame: a block's surface is sent whole
      m_ws.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
        if (ec) return;
        self->m_open = true;
        self->m_server.streams.insert(self);
        {
          std::lock_guard lock(self->m_server.keptLock);
          for (const auto& [key, message] : self->m_server.kept) self->enqueue(key, message);
        }
        self->read();
        self->writeNext();
      });
    }

    void enqueue(const std::string& key, const MessagePtr& message) {
      auto [at, added] = m_pending.try_emplace(key, message);
      if (added) {
        m_order.push_back(key);
      } else {
        at->second = message;
        ++m_server.coalescedCount;
      }
      if (m_open) writeNext();
    }

    void close() {
      beast::error_code ignored;
      beast::get_lowest_layer(m_ws).socket().close(ignored);
    }

   private:
    // The browser sends nothing but pongs: anything larger than this (bytes)
    // closes the connection.
    static constexpr size_t kIncomingMessageLimit = 4096;

    // Reads (and ignores) what the browser sends, to see it leave; the pongs
    // that keep it open come through here too.
    void read() {
      m_ws.async_read(m_incoming, [self = shared_from_this()](beast::error_code ec, size_t) {
        if (ec) {
          self->leave(ec);
          return;
        }
        self->m_incoming.consume(self->m_incoming.size());
        self->read();
      });
    }

    // The connection failed, closed or timed out (the timeout goes to the
    // read or the write, whichever finishes first).
    void leave(beast::error_code ec) {
      if (ec == beast::error::timeout) ++m_server.timedOutCount;
      m_server.streams.erase(shared_from_this());
    }

    void writeNext() {
      if (m_writing || m_order.empty()) return;
      const std::string key = m_order.front();
      m_order.pop_front();
      MessagePtr message = m_pending[key];
      m_pending.erase(key);
      m_writing = true;
      m_ws.binary(message->binary);
      // The message must be taken whole in time, however slowly the client reads.
      m_writeDeadline.expires_after(m_server.limits.writeTimeout);
      // The write it times (a handler already queued when the write ended
      // must not close the client during the next one).
      const uint64_t write = ++m_writes;
      m_writeDeadline.async_wait([weak = weak_from_this(), write](beast::error_code ec) {
        const auto self = weak.lock();
        if (ec || !self || !self->m_writing || self->m_writes != write) return;
        ++self->m_server.timedOutCount;
        self->close();
      });
      m_ws.async_write(asio::buffer(message->bytes),
                       [self = shared_from_this(), message](beast::error_code ec, size_t) {
                         self->m_writing = false;
                         self->m_writeDeadline.cancel();
                         if (ec) {
                           self->leave(ec);
                           return;
                         }
                         self->writeNext();
                       });
    }

    websocket::stream<beast::tcp_stream> m_ws;
    Impl& m_server;
    Slot m_slot;
    beast::flat_buffer m_incoming;
    std::deque<std::string> m_order;
    std::map<std::string, MessagePtr> m_pending;
    bool m_writing = false, m_open = false;
    asio::steady_timer m_writeDeadline;
    uint64_t m_writes = 0;  // writes begun
  };

  // One HTTP connection: a file, the manifest, or the upgrade to /stream.
  class Request : public std::enable_shared_from_this<Request> {
   public:
    Request(tcp::socket socket, Impl& server, Slot slot)
        : m_stream(std::move(socket)), m_server(server), m_slot(std::move(slot)) {}

    void start() {
      m_parser.header_limit(kHeaderLimit);
      m_parser.body_limit(kBodyLimit);
      m_stream.expires_after(m_server.limits.requestTimeout);
      http::async_read(m_stream, m_buffer, m_parser, [self = shared_from_this()](beast::error_code ec, size_t) {
        if (ec == beast::error::timeout) ++self->m_server.timedOutCount;
        if (!ec) self->answer();
      });
    }

   private:
    // A GET has no body, and a browser's headers take a few hundred bytes.
    static constexpr uint32_t kHeaderLimit = 8192;  // bytes
    static constexpr uint64_t kBodyLimit = 1024;    // bytes

    void answer() {
      const http::request<http::string_body>& request = m_parser.get();
      const auto hosts = request.equal_range(http::field::host);
      const auto originAt = request.find(http::field::origin);
      const std::optional<std::string_view> origin =
          originAt == request.end() ? std::nullopt : std::optional<std::string_view>(standard(originAt->value()));
      const std::string refusal = liveRequestRefusal(int(std::distance(hosts.first, hosts.second)),
                                                     standard(request[http::field::host]), origin, m_server.port);
      if (!refusal.empty()) {
        ++m_server.refusedCount;
        respond(http::status::forbidden, "text/plain", refusal + "\n");
        return;
      }
      if (request.method() != http::verb::get) {
        respond(http::status::method_not_allowed, "text/plain", "the live view answers GET only\n");
        return;
      }
      const std::string target(request.target());
      if (websocket::is_upgrade(request)) {
        if (target != "/stream") {
          respond(http::status::not_found, "text/plain", target + ": the WebSocket is at /stream\n");
          return;
        }
        ++m_server.clientCount;
        m_stream.expires_never();  // the WebSocket keeps its own time (Stream::start)
        std::make_shared<Stream>(std::move(m_stream), m_server, std::move(m_slot))->start(m_parser.release());
        return;
      }
      std::string path = target.substr(0, target.find('?'));
      if (path == "/") path = "/index.html";
      if (path == "/data/manifest.js") {
        respond(http::status::ok, contentType(path), m_server.manifest);
      } else if (path == "/index.html" || path == "/viewer.js") {
        std::ifstream in(m_server.assets / path.substr(1), std::ios::binary);
        std::ostringstream bytes;
        bytes << in.rdbuf();
        respond(in ? http::status::ok : http::status::internal_server_error, contentType(path), bytes.str());
      } else {
        respond(http::status::not_found, "text/plain",
                path + ": not here (the live view serves /, /viewer.js, /data/manifest.js, /stream)\n");
      }
    }

    // Answers and closes; a client that does not take the answer within the
    // request timeout is closed too.
    void respond(http::status status, const std::string& type, std::string body) {
      auto response = std::make_shared<http::response<http::string_body>>();
      response->version(m_parser.get().version());
      response->keep_alive(false);
      response->result(status);
      response->set(http::field::cache_control, "no-store");
      response->set(http::field::content_type, type);
      // A refusal or a 404 repeats what the client sent: plain text it stays.
      response->set("X-Content-Type-Options", "nosniff");
      response->body() = std::move(body);
      response->prepare_payload();
      m_stream.expires_after(m_server.limits.requestTimeout);
      http::async_write(m_stream, *response, [self = shared_from_this(), response](beast::error_code ec, size_t) {
        if (ec == beast::error::timeout) ++self->m_server.timedOutCount;
        beast::error_code ignored;
        self->m_stream.socket().shutdown(tcp::socket::shutdown_send, ignored);
      });
    }

    beast::tcp_stream m_stream;
    Impl& m_server;
    Slot m_slot;
    beast::flat_buffer m_buffer;
    http::request_parser<http::string_body> m_parser;
  };

  void accept() {
    acceptor.async_accept([this](beast::error_code ec, tcp::socket socket) {
      if (!acceptor.is_open()) return;  // the server is closing
      if (ec) {
        // No descriptor left (EMFILE, ENFILE) or a connection gone before it
        // was taken: accepting again at once would fail again at once.
        ++acceptErrorCount;
        acceptPause.expires_after(limits.acceptRetry);
        acceptPause.async_wait([this](beast::error_code waitError) {
          if (!waitError) accept();
        });
        return;
      }
      if (open.load() >= limits.maxConnections) {
        ++overLimitCount;
        beast::error_code ignored;
        socket.close(ignored);
      } else {
        std::make_shared<Request>(std::move(socket), *this, Slot(open))->start();
      }
      accept();
    });
  }
};

LiveServer::LiveServer(int port, std::filesystem::path assets, std::string manifest, Limits limits)
    : m_impl(std::make_unique<Impl>()) {
  if (limits.maxConnections < 1 || limits.requestTimeout.count() <= 0 || limits.streamIdleTimeout.count() <= 0 ||
      limits.writeTimeout.count() <= 0 ||
      limits.acceptRetry.count() <= 0)
    throw std::invalid_argument("the live view's limits must be positive (connections, timeouts and retry pause)");
  m_impl->limits = limits;
  m_impl->assets = std::move(assets);
  m_impl->manifest = std::move(manifest);
  beast::error_code ec;
  const tcp::endpoint endpoint(asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port));
  m_impl->acceptor.open(endpoint.protocol(), ec);
  if (!ec) m_impl->acceptor.set_option(asio::socket_base::reuse_address(true), ec);
  if (!ec) m_impl->acceptor.bind(endpoint, ec);
  if (!ec) m_impl->acceptor.listen(asio::socket_base::max_listen_connections, ec);
  if (ec)
    throw std::runtime_error("the live view cannot listen on 127.0.0.1:" + std::to_string(port) + ": " + ec.message());
  m_impl->port = m_impl->acceptor.local_endpoint().port();
  m_impl->accept();
  m_impl->thread = std::thread([impl = m_impl.get()] { impl->io.run(); });
}

LiveServer::~LiveServer() {
  asio::post(m_impl->io, [impl = m_impl.get()] {
    beast::error_code ignored;
    impl->acceptor.close(ignored);
    impl->acceptPause.cancel();
    for (const auto& stream : impl->streams) stream->close();
    impl->streams.clear();
    impl->io.stop();
  });
  if (m_impl->thread.joinable()) m_impl->thread.join();
}

int LiveServer::port() const { return m_impl->port; }
uint64_t LiveServer::clients() const { return m_impl->clientCount; }
uint64_t LiveServer::coalesced() const { return m_impl->coalescedCount; }
uint64_t LiveServer::refused() const { return m_impl->refusedCount; }
uint64_t LiveServer::overLimit() const { return m_impl->overLimitCount; }
uint64_t LiveServer::timedOut() const { return m_impl->timedOutCount; }
uint64_t LiveServer::acceptErrors() const { return m_impl->acceptErrorCount; }
int LiveServer::openConnections() const { return m_impl->open; }

void LiveServer::send(const std::string& key, std::string bytes, bool binary) {
  auto message = std::make_shared<const Message>(Message{std::move(bytes), binary});
  {
    std::lock_guard lock(m_impl->keptLock);
    auto [at, added] = m_impl->keptIndex.try_emplace(key, m_impl->kept.size());
    if (added) m_impl->kept.push_back({key, message});
    else m_impl->kept[at->second].second = message;
  }
  asio::post(m_impl->io, [impl = m_impl.get(), key, message] {
    for (const auto& stream : impl->streams) stream->enqueue(key, message);
  });
}

}  // namespace trephine::viewer
