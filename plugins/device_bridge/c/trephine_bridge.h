/* SPDX-License-Identifier: MIT
 *
 * The Trephine device bridge: the packets a haptic device program exchanges
 * with a simulation, version 1. A device program (an OpenHaptics servo
 * callback, a Force Dimension or Haply loop) compiles this header and
 * trephine_bridge.c in; they need only the C standard library.
 *
 * Two packets, little-endian, of fixed size:
 *   pose  (device -> simulation, 88 bytes): the device point (mm), its
 *         orientation (unit quaternion w, x, y, z), the buttons (bit i:
 *         button i + 1 held), the device's clock (ns), a sequence number
 *         the device increases by one a sample, and the round trip the
 *         device last measured (so the simulation can report what the
 *         device sees);
 *   force (simulation -> device, 72 bytes): the force on the device (N), the
 *         sequence and device time of the pose it was computed from (so the
 *         device measures the round trip), the simulation's own sequence and
 *         clock, and flags (the simulation's watchdog zeroed the force, the
 *         force was clamped to its limit).
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
 *  80  u32          buttons
 *  84  u32          last round trip (ns, saturating at 2^32 - 1; 0: none measured yet)
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

#define TREPHINE_BRIDGE_VERSION 1u
#define TREPHINE_BRIDGE_MAGIC 0x42505254u /* "TRPB" as little-endian bytes */
#define TREPHINE_BRIDGE_POSE_SIZE 88u
#define TREPHINE_BRIDGE_FORCE_SIZE 72u
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
} trephine_bridge_pose;

typedef struct trephine_bridge_force {
  uint64_t sequence;
  uint64_t answered_sequence;
  uint64_t answered_device_time_ns;
  uint64_t simulation_time_ns;
  double force_n[3];
  uint32_t flags;
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
  TREPHINE_BRIDGE_NULL           /* a null pointer */
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

#ifdef __cplusplus
}
#endif

#endif /* TREPHINE_BRIDGE_H */
