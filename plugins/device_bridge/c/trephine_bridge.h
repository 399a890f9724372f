/* SPDX-License-Identifier: MIT
 *
 * The Trephine device bridge: the packets a haptic device program exchanges
 * with a simulation, version 2. A device program (an OpenHaptics servo
 * callback, a Force Dimension or Haply loop) compiles this header and
 * trephine_bridge.c in; they need only the C standard library.
 *
 * Two packets, little-endian, of fixed size:
 *   pose  (device -> simulation, 112 bytes): the device point (mm), its
 *         orientation (unit quaternion w, x, y, z), the buttons (bit i:
 *         button i + 1 held), the device's clock (ns), a sequence number
 *         the device increases by one a sample, and the round trip the
 *         device last measured (so the simulation can report what the
 *         device sees), the device program's session, and which of the
 *         simulation's forces the device takes (its session and the last
 *         sequence taken: so the simulation knows it is heard);
 *   force (simulation -> device, 80 bytes): the force on the device (N), the
 *         sequence and device time of the pose it was computed from (so the
 *         device measures the round trip), the simulation's own sequence and
 *         clock, its session, and flags (the simulation's watchdog zeroed
 *         the force, the force was clamped to its limit).
 *
 * Sessions: each side picks a random non-zero session id when it starts
 * (trephine_bridge_new_session) and numbers its packets from 1 in it. A
 * receiver takes one sender's session at a time (trephine_bridge_stream):
 * a packet of another session is taken only once the session taken has
 * been quiet for the receiver's watchdog time (the other side restarted, or
 * never was), so a restart on either side recovers within that time and a
 * stray packet never locks the genuine sender out. Within a session a
 * sequence must be newer than the last taken, and no further ahead than
 * the time since then explains.
 *
 * Offsets (bytes)   pose                      force
 *   0  u32          magic "TRPB"              magic "TRPB"
 *   4  u16          version (1)               version (1)
 *   6  u16          kind (1)                  kind (2)
 *   8  u64          sequence                  sequence
 *  16  u64          device time (ns)          answered pose's sequence
 *  24  f64[3]       position (mm)             answered pose's device time (ns, u64)
 *  32                                         simulation time (ns, u64)
 *  40                                         force (N, f64[3])
 *  48  f64[4]       orientation (w, x, y, z)
 *  64                                         flags (u32), reserved (u32, 0)
 *  72                                         session (u64, non-zero)
 *  80  u32          buttons
 *  84  u32          last round trip (ns, saturating at 2^32 - 1; 0: none measured yet)
 *  88  u64          session (non-zero)
 *  96  u64          the simulation session whose forces the device takes (0: none yet)
 * 104  u64          the last force sequence the device took in it
 *
 * Decoding checks everything a packet can get wrong (its size, magic,
 * version, kind, a value that is not a number or out of range) and says
 * which; nothing is read beyond the size given. Sequence numbers wrap.
 */
#ifndef TREPHINE_BRIDGE_H
#define TREPHINE_BRIDGE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define TREPHINE_BRIDGE_VERSION 2u
#define TREPHINE_BRIDGE_MAGIC 0x42505254u /* "TRPB" as little-endian bytes */
#define TREPHINE_BRIDGE_POSE_SIZE 112u
#define TREPHINE_BRIDGE_FORCE_SIZE 80u
#define TREPHINE_BRIDGE_KIND_POSE 1u
#define TREPHINE_BRIDGE_KIND_FORCE 2u

/* Limits a decoded packet must keep. */
#define TREPHINE_BRIDGE_MAX_POSITION_MM 10000.0 /* 10 m from the device's origin */
#define TREPHINE_BRIDGE_UNIT_TOLERANCE 1e-3     /* | |q| - 1 | */
#define TREPHINE_BRIDGE_MAX_FORCE_N 1000.0

/* Force flags. */
#define TREPHINE_BRIDGE_FORCE_WATCHDOG 1u /* the simulation heard no pose in time: the force is zero */
#define TREPHINE_BRIDGE_FORCE_CLAMPED 2u  /* the force was clamped to the simulation's limit */

typedef struct trephine_bridge_pose {
  uint64_t sequence;
  uint64_t device_time_ns;
  double position_mm[3];
  double orientation_wxyz[4];
  uint32_t buttons;
  /* From sending a pose to receiving the force that answers it (its
   * answered_sequence), as the device measured it last (ns; 0: none yet). */
  uint32_t round_trip_ns;
  uint64_t session;        /* the device program's (non-zero) */
  uint64_t heard_session;  /* the simulation's session whose forces it takes (0: none yet) */
  uint64_t heard_sequence; /* the last force sequence it took in that session */
} trephine_bridge_pose;

typedef struct trephine_bridge_force {
  uint64_t sequence;
  uint64_t answered_sequence;
  uint64_t answered_device_time_ns;
  uint64_t simulation_time_ns;
  double force_n[3];
  uint32_t flags;
  uint64_t session; /* the simulation's (non-zero) */
} trephine_bridge_force;

typedef enum trephine_bridge_status {
  TREPHINE_BRIDGE_OK = 0,
  TREPHINE_BRIDGE_WRONG_SIZE,    /* not the packet's size */
  TREPHINE_BRIDGE_BAD_MAGIC,     /* not a bridge packet */
  TREPHINE_BRIDGE_BAD_VERSION,   /* another version of the protocol */
  TREPHINE_BRIDGE_BAD_KIND,      /* a force where a pose was expected, or the other way */
  TREPHINE_BRIDGE_NOT_FINITE,    /* a value that is not a number or infinite */
  TREPHINE_BRIDGE_OUT_OF_RANGE,  /* a position beyond 10 m, a force beyond 1000 N */
  TREPHINE_BRIDGE_NOT_UNIT,      /* an orientation that is not a unit quaternion */
  TREPHINE_BRIDGE_RESERVED_SET,  /* a reserved field that is not zero */
  TREPHINE_BRIDGE_NULL,          /* a null pointer */
  TREPHINE_BRIDGE_NO_SESSION     /* a session of 0 */
} trephine_bridge_status;

/* Writes the packet into `out` (TREPHINE_BRIDGE_POSE_SIZE or _FORCE_SIZE
 * bytes). Returns TREPHINE_BRIDGE_OK, or the reason the values cannot be
 * sent (nothing that would be refused at the other end is written). */
trephine_bridge_status trephine_bridge_encode_pose(const trephine_bridge_pose* pose, unsigned char* out);
trephine_bridge_status trephine_bridge_encode_force(const trephine_bridge_force* force, unsigned char* out);

/* Reads a packet of `size` bytes; `out` is written only when it is valid. */
trephine_bridge_status trephine_bridge_decode_pose(const unsigned char* in, size_t size, trephine_bridge_pose* out);
trephine_bridge_status trephine_bridge_decode_force(const unsigned char* in, size_t size, trephine_bridge_force* out);

/* What a status means, in a few words. */
const char* trephine_bridge_status_text(trephine_bridge_status status);

/* Whether sequence `next` comes after `last`, with wrap-around (the
 * difference read as a signed 64-bit number is positive). */
int trephine_bridge_is_newer(uint64_t last, uint64_t next);

/* A new session id: random, never 0 (from /dev/urandom where there is one,
 * mixed with the time and an address so two programs started together
 * differ even without it). */
uint64_t trephine_bridge_new_session(void);

/* Which packets of the other side a receiver takes: one session at a time,
 * and in it sequences that move forward no faster than a sender can. */
typedef struct trephine_bridge_stream {
  uint64_t session;   /* the session taken (0: none yet) */
  uint64_t sequence;  /* the last sequence taken in it */
  uint64_t taken_ns;  /* when (the receiver's clock) */
  uint64_t quiet_ns;  /* another session is taken once this one has been quiet this long */
  double max_rate_hz; /* a sender's sequence advances at most this many a second */
  uint64_t sessions;  /* sessions taken so far */
} trephine_bridge_stream;

typedef enum trephine_bridge_verdict {
  TREPHINE_BRIDGE_TAKE = 0,      /* newer, in the session taken */
  TREPHINE_BRIDGE_NEW_SESSION,   /* another session, to take: none yet, or the one taken went quiet */
  TREPHINE_BRIDGE_STALE,         /* not newer than the last taken (repeated, reordered) */
  TREPHINE_BRIDGE_TOO_FAR_AHEAD, /* further ahead than the time since the last taken explains */
  TREPHINE_BRIDGE_OTHER_SESSION  /* another session while the one taken is still heard */
} trephine_bridge_verdict;

/* quiet_s: the receiver's watchdog time; max_rate_hz: 0 takes 100 kHz. */
void trephine_bridge_stream_init(trephine_bridge_stream* stream, double quiet_s, double max_rate_hz);
/* What to do with a valid packet of `session` and `sequence` that came at
 * `now_ns`. Changes nothing. */
trephine_bridge_verdict trephine_bridge_stream_judge(const trephine_bridge_stream* stream, uint64_t session,
                                                     uint64_t sequence, uint64_t now_ns);
/* Takes it (after TAKE or NEW_SESSION). */
void trephine_bridge_stream_take(trephine_bridge_stream* stream, uint64_t session, uint64_t sequence, uint64_t now_ns);

#ifdef __cplusplus
}
#endif

#endif /* TREPHINE_BRIDGE_H */
