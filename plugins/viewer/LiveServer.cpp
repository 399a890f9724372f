#include "plugins/viewer/LiveServer.h"

#include <atomic>
#include <utility>  // before Asio: Boost 1.74's awaitable.hpp uses std::exchange without it

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/address.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <deque>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

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

  asio::io_context io;
  tcp::acceptor acceptor{io};
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
  std::atomic<uint64_t> clientCount{0}, coalescedCount{0};

  // One WebSocket client: its keys waiting to be written (each once, with its
  // latest message).
  class Stream : public std::enable_shared_from_this<Stream> {
   public:
    Stream(tcp::socket socket, Impl& server) : m_ws(std::move(socket)), m_server(server) {}

    void start(http::request<http::string_body> request) {
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
      m_ws.next_layer().close(ignored);
    }

   private:
    // Reads (and ignores) what the browser sends, to see it leave.
    void read() {
      m_ws.async_read(m_incoming, [self = shared_from_this()](beast::error_code ec, size_t) {
        if (ec) {
          self->m_server.streams.erase(self);
          return;
        }
        self->m_incoming.consume(self->m_incoming.size());
        self->read();
      });
    }

    void writeNext() {
      if (m_writing || m_order.empty()) return;
      const std::string key = m_order.front();
      m_order.pop_front();
      MessagePtr message = m_pending[key];
      m_pending.erase(key);
      m_writing = true;
      m_ws.binary(message->binary);
      m_ws.async_write(asio::buffer(message->bytes),
                       [self = shared_from_this(), message](beast::error_code ec, size_t) {
                         self->m_writing = false;
                         if (ec) {
                           self->m_server.streams.erase(self);
                           return;
                         }
                         self->writeNext();
                       });
    }

    websocket::stream<tcp::socket> m_ws;
    Impl& m_server;
    beast::flat_buffer m_incoming;
    std::deque<std::string> m_order;
    std::map<std::string, MessagePtr> m_pending;
    bool m_writing = false, m_open = false;
  };

  // One HTTP connection: a file, the manifest, or the upgrade to /stream.
  class Request : public std::enable_shared_from_this<Request> {
   public:
    Request(tcp::socket socket, Impl& server) : m_socket(std::move(socket)), m_server(server) {}

    void start() {
      http::async_read(m_socket, m_buffer, m_request, [self = shared_from_this()](beast::error_code ec, size_t) {
        if (!ec) self->answer();
      });
    }

   private:
    void answer() {
      const std::string target(m_request.target());
      if (websocket::is_upgrade(m_request)) {
        if (target == "/stream") {
          ++m_server.clientCount;
          std::make_shared<Stream>(std::move(m_socket), m_server)->start(std::move(m_request));
        }
        return;
      }
      auto response = std::make_shared<http::response<http::string_body>>();
      response->version(m_request.version());
      response->keep_alive(false);
      response->set(http::field::cache_control, "no-store");
      std::string path = target.substr(0, target.find('?'));
      if (path == "/") path = "/index.html";
      if (path == "/data/manifest.js") {
        response->result(http::status::ok);
        response->set(http::field::content_type, contentType(path));
        response->body() = m_server.manifest;
      } else if (path == "/index.html" || path == "/viewer.js") {
        std::ifstream in(m_server.assets / path.substr(1), std::ios::binary);
        std::ostringstream bytes;
        bytes << in.rdbuf();
        response->result(in ? http::status::ok : http::status::internal_server_error);
        response->set(http::field::content_type, contentType(path));
        response->body() = bytes.str();
      } else {
        response->result(http::status::not_found);
        response->set(http::field::content_type, "text/plain");
        response->body() = path + ": not here (the live view serves /, /viewer.js, /data/manifest.js, /stream)\n";
      }
      response->prepare_payload();
      http::async_write(m_socket, *response, [self = shared_from_this(), response](beast::error_code, size_t) {
        beast::error_code ignored;
        self->m_socket.shutdown(tcp::socket::shutdown_send, ignored);
      });
    }

    tcp::socket m_socket;
    Impl& m_server;
    beast::flat_buffer m_buffer;
    http::request<http::string_body> m_request;
  };

  void accept() {
    acceptor.async_accept([this](beast::error_code ec, tcp::socket socket) {
      if (ec) return;  // closed
      std::make_shared<Request>(std::move(socket), *this)->start();
      accept();
    });
  }
};

LiveServer::LiveServer(int port, std::filesystem::path assets, std::string manifest)
    : m_impl(std::make_unique<Impl>()) {
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
    for (const auto& stream : impl->streams) stream->close();
    impl->streams.clear();
    impl->io.stop();
  });
  if (m_impl->thread.joinable()) m_impl->thread.join();
}

int LiveServer::port() const { return m_impl->port; }
uint64_t LiveServer::clients() const { return m_impl->clientCount; }
uint64_t LiveServer::coalesced() const { return m_impl->coalescedCount; }

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
