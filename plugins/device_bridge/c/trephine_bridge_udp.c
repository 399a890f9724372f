/* SPDX-License-Identifier: MIT
 * The device bridge over UDP (trephine_bridge_udp.h). C99 and POSIX. */
#define _POSIX_C_SOURCE 200809L
#include "trephine_bridge_udp.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

struct trephine_bridge_udp {
  int fd;
  trephine_bridge_address local;
};

int trephine_bridge_address_parse(const char* host, uint16_t port, trephine_bridge_address* out) {
  if (!out) return EINVAL;
  struct in_addr parsed;
  if (!host || !host[0]) host = "127.0.0.1";
  if (inet_pton(AF_INET, host, &parsed) != 1) return EINVAL;
  out->ipv4 = ntohl(parsed.s_addr);
  out->port = port;
  return 0;
}

int trephine_bridge_address_equal(const trephine_bridge_address* a, const trephine_bridge_address* b) {
  return a && b && a->ipv4 == b->ipv4 && a->port == b->port;
}

static struct sockaddr_in to_sockaddr(const trephine_bridge_address* address) {
  struct sockaddr_in s;
  memset(&s, 0, sizeof s);
  s.sin_family = AF_INET;
  s.sin_addr.s_addr = htonl(address->ipv4);
  s.sin_port = htons(address->port);
  return s;
}

static trephine_bridge_address from_sockaddr(const struct sockaddr_in* s) {
  trephine_bridge_address a;
  a.ipv4 = ntohl(s->sin_addr.s_addr);
  a.port = ntohs(s->sin_port);
  return a;
}

trephine_bridge_udp* trephine_bridge_udp_open(const trephine_bridge_address* local, int* error) {
  int dummy;
  if (!error) error = &dummy;
  *error = 0;
  if (!local) {
    *error = EINVAL;
    return NULL;
  }
  const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) {
    *error = errno;
    return NULL;
  }
  struct sockaddr_in address = to_sockaddr(local);
  socklen_t length = sizeof address;
  if (bind(fd, (const struct sockaddr*)&address, sizeof address) != 0 ||
      getsockname(fd, (struct sockaddr*)&address, &length) != 0) {
    *error = errno;
    close(fd);
    return NULL;
  }
  trephine_bridge_udp* udp = (trephine_bridge_udp*)malloc(sizeof *udp);
  if (!udp) {
    *error = ENOMEM;
    close(fd);
    return NULL;
  }
  udp->fd = fd;
  udp->local = from_sockaddr(&address);
  return udp;
}

void trephine_bridge_udp_close(trephine_bridge_udp* udp) {
  if (!udp) return;
  close(udp->fd);
  free(udp);
}

trephine_bridge_address trephine_bridge_udp_local(const trephine_bridge_udp* udp) { return udp->local; }

int trephine_bridge_udp_send(trephine_bridge_udp* udp, const trephine_bridge_address* to, const unsigned char* packet,
                             size_t size) {
  if (!udp || !to || !packet) return EINVAL;
  const struct sockaddr_in address = to_sockaddr(to);
  const ssize_t sent =
      sendto(udp->fd, packet, size, MSG_DONTWAIT | MSG_NOSIGNAL, (const struct sockaddr*)&address, sizeof address);
  if (sent < 0) return errno;
  return (size_t)sent == size ? 0 : EMSGSIZE;
}

long trephine_bridge_udp_receive(trephine_bridge_udp* udp, unsigned char* buffer, size_t capacity,
                                 trephine_bridge_address* from) {
  if (!udp || !buffer) return -1;
  struct sockaddr_in address;
  socklen_t length = sizeof address;
  memset(&address, 0, sizeof address);
  /* MSG_TRUNC: the datagram's real size, so a longer one is seen as such. */
  for (;;) {
    const ssize_t got =
        recvfrom(udp->fd, buffer, capacity, MSG_DONTWAIT | MSG_TRUNC, (struct sockaddr*)&address, &length);
    if (got >= 0) {
      if (from) *from = from_sockaddr(&address);
      return (long)got;
    }
    if (errno == EINTR) continue;
    /* EAGAIN: nothing waits. Anything else (an ICMP error reported on the
     * socket) is taken off the socket and reads as nothing now. */
    return -1;
  }
}

int trephine_bridge_udp_wait(trephine_bridge_udp* udp, long timeout_us) {
  if (!udp) return 0;
  struct pollfd p;
  p.fd = udp->fd;
  p.events = POLLIN;
  p.revents = 0;
  const int milliseconds = timeout_us <= 0 ? 0 : (int)((timeout_us + 999) / 1000);
  const int ready = poll(&p, 1, milliseconds);
  return ready > 0 && (p.revents & POLLIN);
}
