// The live view's server over plain sockets: the files it serves, its
// refusals, and the WebSocket's messages: a browser that connects late gets
// the latest message of every key in the order the keys came, and messages
// sent from another thread while it listens arrive whole. Labelled threaded
// (the server has its own thread): it runs under ThreadSanitizer too.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "plugins/viewer/LiveServer.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

using viewer::LiveServer;

class Connection {
 public:
  explicit Connection(int port) {
    m_fd = socket(AF_INET, SOCK_STREAM, 0);
    timeval timeout{5, 0};  // a server that stops answering fails the test, not hangs it
    setsockopt(m_fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(uint16_t(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    m_connected = connect(m_fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
  }
  ~Connection() { close(m_fd); }
  bool connected() const { return m_connected; }
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

std::string get(int port, const std::string& target) {
  Connection c(port);
  EXPECT_TRUE(c.connected());
  c.write("GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  return c.readAll();
}

const char* kUpgrade =
    "GET /stream HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
    "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n";

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
  c.write(kUpgrade);
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

}  // namespace
}  // namespace trephine
