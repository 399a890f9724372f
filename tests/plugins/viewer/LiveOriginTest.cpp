// Whom the live view answers: its own pages by a loopback name on its port,
// and programs that send no Origin; not another site's page, nor its own
// page reached under a rebound name.
#include <gtest/gtest.h>

#include "plugins/viewer/LiveOrigin.h"

namespace trephine {
namespace {

using viewer::isLoopbackHost;
using viewer::isLoopbackOrigin;
using viewer::liveRequestRefusal;

TEST(LiveOriginTest, TheLoopbackNamesOnThisPortOnly) {
  EXPECT_TRUE(isLoopbackHost("127.0.0.1:8080", 8080));
  EXPECT_TRUE(isLoopbackHost("localhost:8080", 8080));
  EXPECT_TRUE(isLoopbackHost("LocalHost:8080", 8080));
  EXPECT_TRUE(isLoopbackHost("[::1]:8080", 8080));
  EXPECT_FALSE(isLoopbackHost("127.0.0.1:8081", 8080)) << "another port is another origin";
  EXPECT_FALSE(isLoopbackHost("127.0.0.1", 8080)) << "no port means 80";
  EXPECT_FALSE(isLoopbackHost("evil.example:8080", 8080)) << "a name rebound to 127.0.0.1";
  EXPECT_FALSE(isLoopbackHost("localhost.evil.example:8080", 8080));
  EXPECT_FALSE(isLoopbackHost("127.0.0.1:8080.evil.example", 8080));
  EXPECT_FALSE(isLoopbackHost("", 8080));
  // Browsers omit the default port.
  EXPECT_TRUE(isLoopbackHost("localhost", 80));
  EXPECT_TRUE(isLoopbackHost("localhost:80", 80));
}

TEST(LiveOriginTest, AnOriginIsHttpAndALoopbackHost) {
  EXPECT_TRUE(isLoopbackOrigin("http://127.0.0.1:8080", 8080));
  EXPECT_TRUE(isLoopbackOrigin("http://localhost:8080", 8080));
  EXPECT_TRUE(isLoopbackOrigin("http://[::1]:8080", 8080));
  EXPECT_FALSE(isLoopbackOrigin("http://evil.example", 8080));
  EXPECT_FALSE(isLoopbackOrigin("http://evil.example:8080", 8080));
  EXPECT_FALSE(isLoopbackOrigin("https://127.0.0.1:8080", 8080)) << "not what the server serves";
  EXPECT_FALSE(isLoopbackOrigin("http://127.0.0.1:9999", 8080)) << "another local server's page";
  EXPECT_FALSE(isLoopbackOrigin("null", 8080)) << "a page opened from the disk, or sandboxed";
  EXPECT_FALSE(isLoopbackOrigin("http://", 8080));
  EXPECT_FALSE(isLoopbackOrigin("", 8080));
}

TEST(LiveOriginTest, ARefusalSaysWhatWasWrongAndWhatIsExpected) {
  EXPECT_EQ(liveRequestRefusal(1, "127.0.0.1:8080", std::nullopt, 8080), "") << "a program without an Origin";
  EXPECT_EQ(liveRequestRefusal(1, "localhost:8080", "http://localhost:8080", 8080), "");
  const std::string host = liveRequestRefusal(1, "evil.example:8080", std::nullopt, 8080);
  EXPECT_NE(host.find("Host 'evil.example:8080'"), std::string::npos) << host;
  EXPECT_NE(host.find("127.0.0.1:8080"), std::string::npos) << host;
  const std::string origin = liveRequestRefusal(1, "127.0.0.1:8080", "http://evil.example", 8080);
  EXPECT_NE(origin.find("Origin 'http://evil.example'"), std::string::npos) << origin;
  EXPECT_NE(liveRequestRefusal(0, "", std::nullopt, 8080).find("one Host header (0 given)"), std::string::npos);
  EXPECT_NE(liveRequestRefusal(2, "127.0.0.1:8080", std::nullopt, 8080).find("(2 given)"), std::string::npos);
  EXPECT_NE(liveRequestRefusal(1, "127.0.0.1:8080", "", 8080), "") << "an Origin present but empty";
}

}  // namespace
}  // namespace trephine
