#include "plugins/viewer/LiveOrigin.h"

#include <algorithm>
#include <array>
#include <cctype>

namespace trephine::viewer {

namespace {

bool equalIgnoringCase(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

constexpr std::array<std::string_view, 3> kLoopbackNames{"127.0.0.1", "localhost", "[::1]"};
constexpr int kDefaultHttpPort = 80;

}  // namespace

bool isLoopbackHost(std::string_view host, int port) {
  const std::string suffix = ":" + std::to_string(port);
  for (std::string_view name : kLoopbackNames) {
    if (equalIgnoringCase(host, std::string(name) + suffix)) return true;
    if (port == kDefaultHttpPort && equalIgnoringCase(host, name)) return true;
  }
  return false;
}

bool isLoopbackOrigin(std::string_view origin, int port) {
  constexpr std::string_view scheme = "http://";
  if (origin.size() <= scheme.size() || !equalIgnoringCase(origin.substr(0, scheme.size()), scheme)) return false;
  return isLoopbackHost(origin.substr(scheme.size()), port);
}

std::string liveRequestRefusal(int hostCount, std::string_view host, const std::optional<std::string_view>& origin,
                               int port) {
  const std::string expected = "127.0.0.1:" + std::to_string(port) + ", localhost:" + std::to_string(port) +
                               " or [::1]:" + std::to_string(port);
  if (hostCount != 1)
    return "a request needs one Host header (" + std::to_string(hostCount) + " given), naming " + expected;
  if (!isLoopbackHost(host, port))
    return "Host '" + std::string(host) + "' is not this server: the live view answers only " + expected;
  if (origin && !isLoopbackOrigin(*origin, port))
    return "Origin '" + std::string(*origin) + "' is another site: the live view answers only its own pages (http://" +
           expected + ")";
  return {};
}

}  // namespace trephine::viewer
