/* SPDX-License-Identifier: MIT
 *
 * The device bridge's safety, the same on both sides: a watchdog that
 * takes the force to zero when the other side goes quiet, and a limit on
 * the force a device is commanded.
 *
 * The watchdog holds a gain in [0, 1] that multiplies the force. While the
 * other side is heard (a new, valid packet at least every `timeout`), the
 * gain is 1. Once it has been quiet for longer than `timeout`, the gain
 * falls linearly to 0 over `ramp` (a trip); when it is heard again, the gain
 * rises back at the same pace, so neither the cut nor the return is a step.
 * Before the other side was first heard, the gain is 0.
 *
 * A device program calls, in its servo loop: trephine_bridge_watchdog_heard
 * for each new force it decoded, trephine_bridge_watchdog_update once a
 * tick, then trephine_bridge_guard_force for the force to command. Allocation-free, no system calls: fit for a servo loop.
 */
#ifndef TREPHINE_BRIDGE_WATCHDOG_H
#define TREPHINE_BRIDGE_WATCHDOG_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct trephine_bridge_watchdog {
  uint64_t timeout_ns; /* quiet for longer than this: a trip */
  uint64_t ramp_ns;    /* the gain goes from 1 to 0 (or back) in this time */
  uint64_t last_heard_ns;
  uint64_t last_update_ns;
  double gain;
  int heard;   /* the other side was heard at least once */
  int tripped; /* quiet for longer than the timeout now */
  uint64_t trips;
} trephine_bridge_watchdog;

/* timeout and ramp in seconds (ramp 0: the force is cut in one step). */
void trephine_bridge_watchdog_init(trephine_bridge_watchdog* watchdog, double timeout_s, double ramp_s);
/* The other side was heard at `now_ns` (a new, valid packet). */
void trephine_bridge_watchdog_heard(trephine_bridge_watchdog* watchdog, uint64_t now_ns);
/* Moves the gain on to `now_ns` and returns it. Returns 1 in *tripped_now
 * (if given) on the call where a trip begins, so the caller logs it once. */
double trephine_bridge_watchdog_update(trephine_bridge_watchdog* watchdog, uint64_t now_ns, int* tripped_now);

/* The force a device is to be commanded: `force_n` times the watchdog's
 * gain (as its last update left it), scaled down (direction kept) to at
 * most `max_force_n`. A force that is not finite is commanded as zero.
 * Returns 1 when the force was limited. */
int trephine_bridge_guard_force(const trephine_bridge_watchdog* watchdog, const double force_n[3], double max_force_n,
                                double out_n[3]);

#ifdef __cplusplus
}
#endif

#endif /* TREPHINE_BRIDGE_WATCHDOG_H */
