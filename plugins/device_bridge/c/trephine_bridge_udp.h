/* SPDX-License-Identifier: MIT
 *
 * The Trephine device bridge over UDP (another machine, or the same one):
 * one datagram per packet (trephine_bridge.h), IPv4, a non-blocking socket,
 * so neither side's loop ever waits on the network. A datagram lost is a
 * sample lost: the sequence numbers tell. Each side keeps the newest packet
 * and drops older ones.
 *
 * Who may talk: a socket binds to 127.0.0.1 unless given another address;
 * the caller checks each datagram's sender (trephine_bridge_udp_receive
 * gives it) against the peer it expects. Needs POSIX sockets.
 */
#ifndef TREPHINE_BRIDGE_UDP_H
#define TREPHINE_BRIDGE_UDP_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* An IPv4 address and port, both in host byte order. */
typedef struct trephine_bridge_address {
  uint32_t ipv4;
  uint16_t port;
} trephine_bridge_address;

/* Reads a dotted IPv4 address ("127.0.0.1"; NULL or "" for 127.0.0.1).
 * Returns 0, or EINVAL for anything else (names are not looked up: the
 * haptic side never waits on a resolver). */
int trephine_bridge_address_parse(const char* host, uint16_t port, trephine_bridge_address* out);
/* Whether two addresses are the same host and port. */
int trephine_bridge_address_equal(const trephine_bridge_address* a, const trephine_bridge_address* b);

typedef struct trephine_bridge_udp trephine_bridge_udp;

/* A non-blocking socket bound to `local` (port 0: any free port). Returns
 * NULL and sets *error (an errno value) on failure. */
trephine_bridge_udp* trephine_bridge_udp_open(const trephine_bridge_address* local, int* error);
void trephine_bridge_udp_close(trephine_bridge_udp* udp);
/* The address the socket is bound to (its port when 0 was asked). */
trephine_bridge_address trephine_bridge_udp_local(const trephine_bridge_udp* udp);

/* Sends one packet to `to` without waiting. Returns 0, or the errno value
 * (EAGAIN: the socket's buffer is full and the packet was dropped). */
int trephine_bridge_udp_send(trephine_bridge_udp* udp, const trephine_bridge_address* to, const unsigned char* packet,
                             size_t size);
/* Takes the next waiting datagram without waiting: copies at most
 * `capacity` bytes into `buffer`, sets *from to its sender, and returns the
 * datagram's whole size (larger than `capacity` when it was cut: a packet
 * of the wrong size), or -1 when none waits. */
long trephine_bridge_udp_receive(trephine_bridge_udp* udp, unsigned char* buffer, size_t capacity,
                                 trephine_bridge_address* from);
/* Whether a datagram waits, waiting at most `timeout_us` (0: just look).
 * Returns 1 when one waits, 0 when none came in time. */
int trephine_bridge_udp_wait(trephine_bridge_udp* udp, long timeout_us);

#ifdef __cplusplus
}
#endif

#endif /* TREPHINE_BRIDGE_UDP_H */
