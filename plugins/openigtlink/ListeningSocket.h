#pragma once
// The TCP listener both OpenIGTLink servers (the device's and the exporter's)
// open, and the clock their client timeouts are measured on.
#include <cstdint>
#include <string>

namespace trephine::openigtlink {

struct Listener {
  int fd = -1;        // non-blocking, close-on-exec; the caller closes it
  uint16_t port = 0;  // the one bound: the one asked for, or the system's pick for 0
};

// Listens on host:port (host a dotted IPv4 address, as given: loopback unless
// a scene asks for another). Throws std::runtime_error saying which address
// and why when it cannot.
Listener listenOn(const std::string& host, uint16_t port);

// Monotonic time in ns, for timeouts (never the wall clock, which can jump).
uint64_t steadyNs();

}  // namespace trephine::openigtlink
