/* SPDX-License-Identifier: MIT
 *
 * The Trephine device bridge over shared memory (one machine): a POSIX
 * shared memory object holding the latest pose and the latest force, each
 * in a slot that one side writes and the other reads without waiting or
 * locking (a sequence lock: the writer marks the slot odd while it writes;
 * a reader that saw the mark change, or odd, tries again at its next tick).
 * Either side's loop takes the latest value and never waits on the other.
 * The slots hold encoded packets (trephine_bridge.h), so the reader decodes
 * and checks what it reads like any packet. Needs C11 atomics and POSIX
 * shm_open/mmap (link -lrt on old C libraries).
 */
#ifndef TREPHINE_BRIDGE_SHM_H
#define TREPHINE_BRIDGE_SHM_H

#include <stddef.h>
#include <stdint.h>

#include "trephine_bridge.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct trephine_bridge_shm trephine_bridge_shm;

/* Opens the shared memory object `name` ("/trephine-bridge" and the like: a
 * leading slash, no other), creating it when `create` is non-zero and it is
 * missing (new, exclusively, owner-only). An object that exists is taken
 * only when it is this user's and no one else may read or write it.
 * Returns NULL and sets *error on failure: an errno value, EPROTO for an
 * object that is not a bridge of this version, EPERM for one of another
 * user's or open to others (anyone who can write it drives the device). */
trephine_bridge_shm* trephine_bridge_shm_open(const char* name, int create, int* error);

/* Whether the object still holds the whole bridge (another process may
 * truncate it; reading a truncated mapping would end this process with
 * SIGBUS). One fstat: call it before reading or writing, once a tick. Once
 * it says 0 the bridge is gone for good: close it. */
int trephine_bridge_shm_intact(trephine_bridge_shm* shm);
/* For a process that must survive the object's truncation whatever the
 * timing (the simulation): a SIGBUS inside this mapping no longer ends the
 * process; the mapping reads as never written from then on and
 * trephine_bridge_shm_intact says 0. Installs a process-wide SIGBUS handler
 * (once; any other SIGBUS goes to the handler there was). Returns 0, or -1
 * when it cannot (8 mappings at most). */
int trephine_bridge_shm_guard_truncation(trephine_bridge_shm* shm);
/* Unmaps it; the side that created it also removes the name when `unlink` is non-zero. */
void trephine_bridge_shm_close(trephine_bridge_shm* shm, const char* name, int unlink);

/* The device side writes poses and reads forces; the simulation the other way. */
void trephine_bridge_shm_write_pose(trephine_bridge_shm* shm, const unsigned char packet[TREPHINE_BRIDGE_POSE_SIZE]);
void trephine_bridge_shm_write_force(trephine_bridge_shm* shm, const unsigned char packet[TREPHINE_BRIDGE_FORCE_SIZE]);
/* Copies the slot's latest packet into `out`; returns 1 when the copy is
 * whole, 0 when a write was under way (nothing usable: try at the next tick)
 * or nothing was ever written. */
int trephine_bridge_shm_read_pose(const trephine_bridge_shm* shm, unsigned char out[TREPHINE_BRIDGE_POSE_SIZE]);
int trephine_bridge_shm_read_force(const trephine_bridge_shm* shm, unsigned char out[TREPHINE_BRIDGE_FORCE_SIZE]);

/* The simulation's side claims the object, so that a second simulation on
 * the same name is refused instead of answering the same device: returns 0
 * when this process (`pid`) holds it now, or the process id of the live
 * simulation that does. A holder that has died is replaced, and so is one
 * whose pid now belongs to another process (its start time differs: Linux). */
long trephine_bridge_shm_claim(trephine_bridge_shm* shm, long pid);
/* Gives the claim up (when `pid` holds it). */
void trephine_bridge_shm_release(trephine_bridge_shm* shm, long pid);

/* How many times the pose (force) slot was written so far, in one atomic
 * load: a cheap test for a new packet in a loop that polls for one. */
uint64_t trephine_bridge_shm_pose_writes(const trephine_bridge_shm* shm);
uint64_t trephine_bridge_shm_force_writes(const trephine_bridge_shm* shm);

#ifdef __cplusplus
}
#endif

#endif /* TREPHINE_BRIDGE_SHM_H */
