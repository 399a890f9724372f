/* SPDX-License-Identifier: MIT
 * The device bridge's watchdog and force limit (trephine_bridge_watchdog.h). C99. */
#include "trephine_bridge_watchdog.h"

#include <math.h>

void trephine_bridge_watchdog_init(trephine_bridge_watchdog* w, double timeout_s, double ramp_s) {
  w->timeout_ns = timeout_s > 0 ? (uint64_t)(timeout_s * 1e9) : 0;
  w->ramp_ns = ramp_s > 0 ? (uint64_t)(ramp_s * 1e9) : 0;
  w->last_heard_ns = 0;
  w->last_update_ns = 0;
  w->gain = 0;
  w->heard = 0;
  w->tripped = 0;
  w->trips = 0;
}

void trephine_bridge_watchdog_heard(trephine_bridge_watchdog* w, uint64_t now_ns) {
  if (!w->heard) w->last_update_ns = now_ns;
  w->heard = 1;
  w->last_heard_ns = now_ns;
}

double trephine_bridge_watchdog_update(trephine_bridge_watchdog* w, uint64_t now_ns, int* tripped_now) {
  if (tripped_now) *tripped_now = 0;
  if (!w->heard) return w->gain = 0;
  const int quiet = now_ns > w->last_heard_ns && now_ns - w->last_heard_ns > w->timeout_ns;
  if (quiet && !w->tripped) {
    ++w->trips;
    if (tripped_now) *tripped_now = 1;
  }
  w->tripped = quiet;
  const double elapsed = now_ns > w->last_update_ns ? (double)(now_ns - w->last_update_ns) : 0.0;
  w->last_update_ns = now_ns;
  /* The gain moves toward 0 (quiet) or 1 (heard) at 1 / ramp. */
  const double step = w->ramp_ns > 0 ? elapsed / (double)w->ramp_ns : 1.0;
  if (quiet)
    w->gain = w->gain - step > 0 ? w->gain - step : 0;
  else
    w->gain = w->gain + step < 1 ? w->gain + step : 1;
  return w->gain;
}

int trephine_bridge_guard_force(const trephine_bridge_watchdog* w, const double force_n[3], double max_force_n,
                                double out_n[3]) {
  const double gain = w->gain;
  double norm2 = 0;
  for (int i = 0; i < 3; ++i) {
    if (!isfinite(force_n[i])) {
      out_n[0] = out_n[1] = out_n[2] = 0;
      return 1;
    }
    out_n[i] = gain * force_n[i];
    norm2 += out_n[i] * out_n[i];
  }
  const double norm = sqrt(norm2);
  if (!(max_force_n >= 0)) max_force_n = 0;
  if (norm > max_force_n) {
    const double scale = norm > 0 ? max_force_n / norm : 0;
    for (int i = 0; i < 3; ++i) out_n[i] *= scale;
    return 1;
  }
  return 0;
}
