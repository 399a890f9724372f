// The live view's server over plain sockets: the files it serves, its
// refusals, and the WebSocket's messages: a browser that connects late gets
// the latest message of every key in the order the keys came, and messages
// sent from another thread while it listens arrive whole. Then misbehaving
// clients: other sites' pages and rebound names are refused, slow and silent
// connections are closed, connections beyond the limit are turned away, and
// running out of descriptors only pauses accepting. Labelled threaded (the
// server has its own thread): it runs under ThreadSanitizer too.
#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <atomic>
#include <fstream>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "plugins/viewer/LiveServer.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

using viewer::LiveServer;

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

// Whether `condition` holds within `limit`, looking every 10 ms.
bool eventually(const std::function<bool()>& condition, milliseconds limit = milliseconds(3000)) {
  for (const auto end = Clock::now() + limit; Clock::now() < end; std::this_thread::sleep_for(milliseconds(10)))
    if (condition()) return true;
  return condition();
}

class Connection {
 public:
  // A socket not yet connected: connect() needs no new descriptor.
  Connection() {
    m_fd = socket(AF_INET, SOCK_STREAM, 0);
    timeval timeout{5, 0};  // a server that stops answering fails the test, not hangs it
    setsockopt(m_fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  }
  explicit Connection(int port) : Connection() { connectTo(port); }
  ~Connection() { close(m_fd); }
  bool connectTo(int port) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(uint16_t(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    m_connected = connect(m_fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
    return m_connected;
  }
  // A small receive buffer (bytes), set before connecting: a client that
  // does not read holds up the server's writes sooner.
  void receiveBuffer(int bytes) { setsockopt(m_fd, SOL_SOCKET, SO_RCVBUF, &bytes, sizeof bytes); }
  bool connected() const { return m_connected; }
  // True when the server closed the connection (end of stream or reset),
  // false when it was still open after the 5 s receive timeout; what was
  // still buffered is read and dropped.
  bool closedByServer() {
    char buffer[65536];
    for (;;) {
      const ssize_t n = recv(m_fd, buffer, sizeof buffer, 0);
      if (n > 0) continue;
      return n == 0 || errno == ECONNRESET;
    }
  }
  // A masked pong frame (RFC 6455: a client masks what it sends) carrying `payload`.
  void pong(const std::string& payload) { write(pongFrame(payload)); }
  // The same, false when the connection is gone (closed by the server).
  bool tryPong(const std::string& payload) {
    const std::string frame = pongFrame(payload);
    return ::send(m_fd, frame.data(), frame.size(), MSG_NOSIGNAL) == ssize_t(frame.size());
  }
  static std::string pongFrame(const std::string& payload) {
    const uint8_t mask[4] = {1, 2, 3, 4};
    std::string frame{char(0x8a), char(0x80 | (payload.size() & 0x7f))};
    frame.append(reinterpret_cast<const char*>(mask), 4);
    for (size_t i = 0; i < payload.size(); ++i) frame += char(payload[i] ^ mask[i % 4]);
    return frame;
  }
  void write(const std::string& bytes) { ASSERT_EQ(::send(m_fd, bytes.data(), bytes.size(), 0), ssize_t(bytes.size())); }
  // Everything until the server closes (an HTTP answer).
  std::string readAll() {
    std::string out;
    char buffer[4096];
    for (ssize_t n; (n = recv(m_fd, buffer, sizeof buffer, 0)) > 0;) out.append(buffer, size_t(n));
    return out;
  }
  // Exactly n bytes (or fewer when the server closes or times out).
  std::string read(size_t n) {
    std::string out;
    char buffer[4096];
    while (out.size() < n) {
      const ssize_t got = recv(m_fd, buffer, std::min(sizeof buffer, n - out.size()), 0);
      if (got <= 0) break;
      out.append(buffer, size_t(got));
    }
    return out;
  }
  // The header of an HTTP answer (through the blank line).
  std::string readHeader() {
    std::string out;
    while (!out.ends_with("\r\n\r\n")) {
      const std::string c = read(1);
      if (c.empty()) break;
      out += c;
    }
    return out;
  }
  // One message: the payloads of unmasked server frames up to the one with
  // FIN set (RFC 6455); `opcode`: the first frame's.
  std::string readFrame(int* opcode) {
    std::string message;
    for (bool first = true;; first = false) {
      bool fin = false;
      int frameOpcode = 0;
      message += readOneFrame(&frameOpcode, &fin);
      if (first) *opcode = frameOpcode;
      if (fin || (first && message.empty() && frameOpcode == 0)) return message;
    }
  }
  std::string readOneFrame(int* opcode, bool* fin) {
    const std::string head = read(2);
    if (head.size() < 2) {
      *fin = true;
      return {};
    }
    *fin = (uint8_t(head[0]) & 0x80) != 0;
    *opcode = uint8_t(head[0]) & 0x0f;
    uint64_t length = uint8_t(head[1]) & 0x7f;
    if (length == 126) {
      const std::string ext = read(2);
      length = (uint64_t(uint8_t(ext[0])) << 8) | uint8_t(ext[1]);
    } else if (length == 127) {
      const std::string ext = read(8);
      length = 0;
      for (char c : ext) length = (length << 8) | uint8_t(c);
    }
    return read(size_t(length));
  }

 private:
  int m_fd = -1;
  bool m_connected = false;
};

struct Assets {
  test::TempDir dir{"trephine-live-assets"};
  Assets() {
    std::ofstream(dir.path() / "index.html") << "<html>viewer</html>";
    std::ofstream(dir.path() / "viewer.js") << "// bundle";
  }
};

std::string getRequest(int port, const std::string& target) {
  return "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n\r\n";
}

std::string get(int port, const std::string& target) {
  Connection c(port);
  EXPECT_TRUE(c.connected());
  c.write(getRequest(port, target));
  return c.readAll();
}

// The upgrade to the WebSocket, as a browser at `host` on a page of `origin`
// (none: a program) sends it.
std::string upgrade(const std::string& host, const std::string& origin = "") {
  return "GET /stream HTTP/1.1\r\nHost: " + host + "\r\n" + (origin.empty() ? "" : "Origin: " + origin + "\r\n") +
         "Upgrade: websocket\r\nConnection: Upgrade\r\n"
         "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n";
}

std::string loopback(int port) { return "127.0.0.1:" + std::to_string(port); }

// Opens the WebSocket stream on `c` with a receive buffer of 4 KiB, so that
// what the client does not read soon fills the server's side.
void openSlowStream(Connection& c, int port) {
  c.receiveBuffer(4096);
  ASSERT_TRUE(c.connectTo(port));
  c.write(upgrade(loopback(port)));
  ASSERT_NE(c.readHeader().find("101"), std::string::npos);
}

// Opens descriptors until there are none left (the soft limit lowered to 256
// first, so that it takes few), and gives them all back when it goes.
class DescriptorsExhausted {
 public:
  DescriptorsExhausted() {
    getrlimit(RLIMIT_NOFILE, &m_saved);
    rlimit lowered = m_saved;
    lowered.rlim_cur = std::min<rlim_t>(m_saved.rlim_cur, 256);
    setrlimit(RLIMIT_NOFILE, &lowered);
    for (int fd; (fd = open("/dev/null", O_RDONLY)) >= 0;) m_held.push_back(fd);
    m_error = errno;
  }
  ~DescriptorsExhausted() {
    for (int fd : m_held) close(fd);
    setrlimit(RLIMIT_NOFILE, &m_saved);
  }
  bool exhausted() const { return m_error == EMFILE && !m_held.empty(); }

 private:
  rlimit m_saved{};
  std::vector<int> m_held;
  int m_error = 0;
};

TEST(LiveServerTest, ServesTheViewerTheManifestAndNothingElse) {
  Assets assets;
  LiveServer server(0, assets.dir.path(), "window.trephineRun = {\"live\": true};");
  ASSERT_GT(server.port(), 0);
  EXPECT_NE(get(server.port(), "/").find("<html>viewer</html>"), std::string::npos);
  EXPECT_NE(get(server.port(), "/viewer.js").find("// bundle"), std::string::npos);
  const std::string manifest = get(server.port(), "/data/manifest.js?x=1");
  EXPECT_NE(manifest.find("200 OK"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("\"live\": true"), std::string::npos) << manifest;
  const std::string other = get(server.port(), "/../../etc/passwd");
  EXPECT_NE(other.find("404"), std::string::npos) << other;
  // A second server on a taken port: a clear error.
  try {
    LiveServer second(server.port(), assets.dir.path(), "");
    ADD_FAILURE() << "two servers on one port";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot listen on 127.0.0.1:" + std::to_string(server.port())),
              std::string::npos)
        << e.what();
  }
}

TEST(LiveServerTest, ALateBrowserGetsTheLatestOfEachKeyInOrderThenWhatFollows) {
  Assets assets;
  LiveServer server(0, assets.dir.path(), "");
  server.send("cells", "C1", true);
  server.send("tool", "T1", true);
  server.send("block/7", "B1", true);
  server.send("tool", "T2", true);  // replaces T1, keeps its place
  Connection c(server.port());
  ASSERT_TRUE(c.connected());
  c.write(upgrade(loopback(server.port())));
  const std::string header = c.readHeader();
  ASSERT_NE(header.find("101"), std::string::npos) << header;
  // RFC 6455's example key and its answer.
  EXPECT_NE(header.find("s3pPLMBiTxaQ9kYGzzhZRbK+xOo="), std::string::npos) << header;
  int opcode = 0;
  EXPECT_EQ(c.readFrame(&opcode), "C1");
  EXPECT_EQ(opcode, 2) << "binary";
  EXPECT_EQ(c.readFrame(&opcode), "T2");
  EXPECT_EQ(c.readFrame(&opcode), "B1");
  // Sent from another thread while connected: every one arrives, whole and
  // in order (the browser keeps up here, so none is skipped).
  std::thread sender([&] {
    for (int i = 0; i < 50; ++i) {
      server.send("block/" + std::to_string(i), std::string(70000, char('a' + i % 26)), true);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  });
  int received = 0;
  std::set<char> letters;
  for (; received < 50; ++received) {
    const std::string frame = c.readFrame(&opcode);
    if (frame.size() != 70000) {
      ADD_FAILURE() << "frame " << received << ": " << frame.size() << " bytes, opcode " << opcode;
      break;
    }
    letters.insert(frame.front());
    EXPECT_EQ(frame.find_first_not_of(frame.front()), std::string::npos) << "a message whole";
  }
  sender.join();
  EXPECT_EQ(received, 50);
  EXPECT_EQ(letters.size(), 26u);
  EXPECT_EQ(server.clients(), 1u);
}


// Limits that make the tests quick: timeouts of a few hundred milliseconds.
LiveServer::Limits quickLimits() {
  LiveServer::Limits limits;
  limits.maxConnections = 4;
  limits.requestTimeout = milliseconds(300);
  limits.streamIdleTimeout = milliseconds(400);
  limits.acceptRetry = milliseconds(50);
  limits.writeTimeout = milliseconds(600);
  return limits;
}

TEST(LiveServerTest, OtherSitesPagesAndReboundNamesAreRefused) {
  Assets assets;
  LiveServer server(0, assets.dir.path(), "window.trephineRun = {};");
  const int port = server.port();
  // Each refused with 403 and no upgrade, and nothing of the stream or the
  // viewer in the answer.
  const std::vector<std::string> refused = {
      upgrade(loopback(port), "http://evil.example"),                          // another site's page
      upgrade(loopback(port), "http://127.0.0.1:" + std::to_string(port + 1)),  // another local server's page
      upgrade(loopback(port), "null"),                                         // a page from the disk
      upgrade("evil.example:" + std::to_string(port)),                         // a name rebound to 127.0.0.1
      upgrade("evil.example:" + std::to_string(port), "http://evil.example:" + std::to_string(port)),
      "GET / HTTP/1.1\r\nHost: evil.example:" + std::to_string(port) + "\r\n\r\n",
      "GET /data/manifest.js HTTP/1.1\r\nHost: evil.example\r\n\r\n",
      "GET / HTTP/1.1\r\n\r\n",                                                // no Host at all
      "GET / HTTP/1.1\r\nHost: " + loopback(port) + "\r\nOrigin: http://evil.example\r\n\r\n",
  };
  for (const std::string& request : refused) {
    Connection c(port);
    ASSERT_TRUE(c.connected());
    c.write(request);
    const std::string answer = c.readAll();
    EXPECT_NE(answer.find("403 Forbidden"), std::string::npos) << request << "\n--\n" << answer;
    EXPECT_NE(answer.find("X-Content-Type-Options: nosniff"), std::string::npos) << "it echoes the request";
    EXPECT_EQ(answer.find("101"), std::string::npos) << request;
    EXPECT_EQ(answer.find("viewer"), std::string::npos) << request;
    EXPECT_EQ(answer.find("trephineRun"), std::string::npos) << request;
  }
  EXPECT_EQ(server.refused(), refused.size());
  EXPECT_EQ(server.clients(), 0u);
  // Its own pages, by any loopback name, and programs without an Origin.
  const std::vector<std::string> accepted = {
      upgrade(loopback(port), "http://127.0.0.1:" + std::to_string(port)),
      upgrade("localhost:" + std::to_string(port), "http://localhost:" + std::to_string(port)),
      upgrade("[::1]:" + std::to_string(port), "http://[::1]:" + std::to_string(port)),
      upgrade(loopback(port)),
  };
  for (const std::string& request : accepted) {
    Connection c(port);
    ASSERT_TRUE(c.connected());
    c.write(request);
    const std::string header = c.readHeader();
    EXPECT_NE(header.find("101 Switching Protocols"), std::string::npos) << request << "\n--\n" << header;
  }
  EXPECT_EQ(server.clients(), accepted.size());
  EXPECT_EQ(server.refused(), refused.size());
  EXPECT_NE(get(port, "/").find("<html>viewer</html>"), std::string::npos);
}

TEST(LiveServerTest, ARequestThatDoesNotArriveInTimeIsClosed) {
  Assets assets;
  LiveServer server(0, assets.dir.path(), "", quickLimits());
  Connection silent(server.port());
  Connection partial(server.port());
  ASSERT_TRUE(silent.connected());
  ASSERT_TRUE(partial.connected());
  partial.write("GET / HTTP/1.1\r\nHost: " + loopback(server.port()) + "\r\n");  // never finished
  const auto start = Clock::now();
  EXPECT_TRUE(silent.closedByServer()) << "still open after 5 s";
  EXPECT_TRUE(partial.closedByServer()) << "still open after 5 s";
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_GE(seconds, 0.25) << "closed before the request timeout (0.3 s)";
  EXPECT_LT(seconds, 2.0) << "closed long after the request timeout (0.3 s)";
  // Counted once the server's read has ended, which may be just after the client sees the close.
  EXPECT_TRUE(eventually([&] { return server.timedOut() == 2; })) << server.timedOut();
  EXPECT_TRUE(eventually([&] { return server.openConnections() == 0; })) << server.openConnections();
  // And the server still answers.
  EXPECT_NE(get(server.port(), "/").find("<html>viewer</html>"), std::string::npos);
}

TEST(LiveServerTest, AWebSocketClientThatStopsReadingIsClosed) {
  Assets assets;
  LiveServer server(0, assets.dir.path(), "", quickLimits());
  Connection c;
  ASSERT_NO_FATAL_FAILURE(openSlowStream(c, server.port()));
  // More than the socket buffers on both sides hold (bytes), then not a byte read.
  const size_t message = 1 << 20;
  for (int i = 0; i < 16; ++i) server.send("block/" + std::to_string(i), std::string(message, 'x'), true);
  EXPECT_TRUE(eventually([&] { return server.timedOut() == 1; })) << "no timeout within 3 s of a 0.4 s idle limit";
  EXPECT_TRUE(eventually([&] { return server.openConnections() == 0; })) << server.openConnections();
  EXPECT_TRUE(c.closedByServer()) << "still open";
}

TEST(LiveServerTest, AWebSocketClientThatAnswersPingsStaysOpen) {
  Assets assets;
  LiveServer server(0, assets.dir.path(), "", quickLimits());
  Connection c(server.port());
  ASSERT_TRUE(c.connected());
  c.write(upgrade(loopback(server.port())));
  ASSERT_NE(c.readHeader().find("101"), std::string::npos);
  // Four idle timeouts (0.4 s) long, with the tool's pose every 50 ms.
  std::atomic<bool> sending{true};
  std::thread sender([&] {
    for (int i = 0; sending; ++i) {
      server.send("tool", "T" + std::to_string(i), true);
      std::this_thread::sleep_for(milliseconds(50));
    }
  });
  int pings = 0, messages = 0;
  for (const auto end = Clock::now() + milliseconds(1600); Clock::now() < end;) {
    int opcode = -1;
    const std::string payload = c.readFrame(&opcode);
    if (opcode == 9) {
      ++pings;
      c.pong(payload);
    } else if (opcode == 2) {
      ++messages;
    } else {
      ADD_FAILURE() << "opcode " << opcode << " (8: the server closed)";
      break;
    }
  }
  sending = false;
  sender.join();
  EXPECT_GE(pings, 2) << "a ping after each half idle timeout (0.2 s) without a message read from the client";
  EXPECT_GE(messages, 10);
  EXPECT_EQ(server.timedOut(), 0u);
  EXPECT_EQ(server.openConnections(), 1);
}

// A client that keeps its connection alive (a pong every 100 ms, as a
// heartbeat) but reads a few hundred bytes at a time: before, it held its
// connection for good (and 16 such held all of them); now a message it does
// not take whole within the write timeout closes it.
TEST(LiveServerTest, AWebSocketClientThatReadsTooSlowlyIsClosed) {
  Assets assets;
  LiveServer server(0, assets.dir.path(), "", quickLimits());
  Connection c;
  ASSERT_NO_FATAL_FAILURE(openSlowStream(c, server.port()));
  server.send("block/0", std::string(size_t(4) << 20, 'x'), true);
  const auto start = Clock::now();
  bool closed = false;
  while (Clock::now() - start < std::chrono::seconds(4) && !closed) {
    closed = !c.tryPong("alive");
    for (int k = 0; k < 2 && !closed; ++k) {
      closed = c.read(256).size() < 256;
      std::this_thread::sleep_for(milliseconds(50));
    }
  }
  EXPECT_TRUE(closed) << "a client 4 MB behind, alive, was never let go";
  EXPECT_TRUE(eventually([&] { return server.timedOut() == 1; })) << server.timedOut();
  EXPECT_TRUE(eventually([&] { return server.openConnections() == 0; })) << server.openConnections();
}

TEST(LiveServerTest, ConnectionsBeyondTheLimitAreClosedAtOnce) {
  Assets assets;
  LiveServer::Limits limits = quickLimits();
  limits.requestTimeout = milliseconds(10000);  // the idle ones stay while the test looks
  LiveServer server(0, assets.dir.path(), "", limits);
  std::vector<std::unique_ptr<Connection>> idle;
  for (int i = 0; i < limits.maxConnections; ++i) {
    idle.push_back(std::make_unique<Connection>(server.port()));
    ASSERT_TRUE(idle.back()->connected());
  }
  ASSERT_TRUE(eventually([&] { return server.openConnections() == limits.maxConnections; }))
      << server.openConnections();
  {
    Connection extra(server.port());
    ASSERT_TRUE(extra.connected()) << "the kernel completes the handshake; the server then closes it";
    extra.write(getRequest(server.port(), "/"));
    const auto start = Clock::now();
    EXPECT_TRUE(extra.closedByServer()) << "one over the limit still open after 5 s";
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 1.0);
    EXPECT_EQ(server.overLimit(), 1u);
  }
  EXPECT_EQ(server.openConnections(), limits.maxConnections);
  idle.clear();  // they leave: there is room again
  ASSERT_TRUE(eventually([&] { return server.openConnections() == 0; })) << server.openConnections();
  EXPECT_NE(get(server.port(), "/").find("<html>viewer</html>"), std::string::npos);
  EXPECT_EQ(server.overLimit(), 1u);
}

TEST(LiveServerTest, RunningOutOfDescriptorsOnlyPausesAccepting) {
  Assets assets;
  LiveServer server(0, assets.dir.path(), "", quickLimits());
  Connection client;  // its descriptor taken while there are some left
  {
    DescriptorsExhausted exhausted;
    ASSERT_TRUE(exhausted.exhausted());
    const auto start = Clock::now();
    ASSERT_TRUE(client.connectTo(server.port()));
    // accept() fails with EMFILE, again after each pause (50 ms), and not
    // more often: at most one more than the pauses that fit.
    EXPECT_TRUE(eventually([&] { return server.acceptErrors() >= 3; })) << server.acceptErrors();
    std::this_thread::sleep_until(start + milliseconds(500));
    const double pauses = std::chrono::duration<double>(Clock::now() - start).count() / 0.050;
    EXPECT_LE(double(server.acceptErrors()), pauses + 1) << "accept() tried again without pausing";
  }
  client.write(getRequest(server.port(), "/"));
  const std::string answer = client.readAll();
  EXPECT_NE(answer.find("200 OK"), std::string::npos) << "not served after the descriptors came back: " << answer;
  EXPECT_NE(answer.find("<html>viewer</html>"), std::string::npos) << answer;
  // And the ones after it.
  EXPECT_NE(get(server.port(), "/viewer.js").find("// bundle"), std::string::npos);
}

}  // namespace
}  // namespace trephine
