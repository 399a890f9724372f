#pragma once
// Who the live view answers: only pages it served itself, reached by a
// loopback name. A page of another site may open a WebSocket to any address
// (browsers send its Origin but do not stop it), and a site whose name is
// rebound to 127.0.0.1 reaches the server under its own name (its Host), so
// both are checked:
//   Host    127.0.0.1:PORT, localhost:PORT or [::1]:PORT (the bare name too
//           when PORT is 80, as browsers omit the default port);
//   Origin  absent (a program, not a page), or http:// and one of those.
// Names compare without regard to case.
#include <optional>
#include <string>
#include <string_view>

namespace trephine::viewer {

bool isLoopbackHost(std::string_view host, int port);
bool isLoopbackOrigin(std::string_view origin, int port);

// Why a request with these headers (none: absent; hostCount: how many Host
// headers it had) is refused by the server on `port`; empty when it is not.
std::string liveRequestRefusal(int hostCount, std::string_view host, const std::optional<std::string_view>& origin,
                               int port);

}  // namespace trephine::viewer
