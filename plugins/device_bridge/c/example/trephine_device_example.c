/* SPDX-License-Identifier: MIT
 *
 * A device program on the device bridge, complete and small: the servo loop
 * of docs/devices.md around a stand-in for a device's SDK (read_device and
 * command_force below; with OpenHaptics, Force Dimension's DHD or Haply's
 * API those calls go there). The stand-in's handle moves down onto the
 * plane z = 0 of scenes/devices/bridge_plane.xml and presses 1 mm into it.
 *
 *   trephine_device_example [SECONDS] [udp HOST PORT]
 *
 * Shared memory (/trephine-bridge) unless udp is given. At the end it prints
 * what it saw: poses sent, forces received, round trips, the last force. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "trephine_bridge.h"
#include "trephine_bridge_shm.h"
#include "trephine_bridge_udp.h"
#include "trephine_bridge_watchdog.h"

static uint64_t clock_ns(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

/* The stand-in device: down from 10 mm over 0.5 s, then held with the
 * sphere's centre at 1.5 mm (a 2.5 mm sphere 1 mm into the plane). */
static void read_device(double t, double position_mm[3], double orientation_wxyz[4], uint32_t* buttons) {
  position_mm[0] = 3.0;
  position_mm[1] = 0.0;
  position_mm[2] = t < 0.5 ? 10.0 - 17.0 * t : 1.5;
  orientation_wxyz[0] = 1.0;
  orientation_wxyz[1] = orientation_wxyz[2] = orientation_wxyz[3] = 0.0;
  *buttons = 0;
}
static double last_commanded[3];
static void command_force(const double force_n[3]) { memcpy(last_commanded, force_n, sizeof last_commanded); }

/* How long a tick polls for the answer to its pose (ns): half a 1 kHz frame. */
static const uint64_t kAwaitNs = 500000u;

/* Whether a valid force is one to take: of the simulation's session taken,
 * newer and not implausibly far ahead; or of a new session once the one
 * taken went quiet (the simulation was started again). Takes it. */
static int take_if_due(trephine_bridge_stream* stream, const trephine_bridge_force* force, uint64_t now) {
  const trephine_bridge_verdict verdict = trephine_bridge_stream_judge(stream, force->session, force->sequence, now);
  if (verdict != TREPHINE_BRIDGE_TAKE && verdict != TREPHINE_BRIDGE_NEW_SESSION) return 0;
  trephine_bridge_stream_take(stream, force->session, force->sequence, now);
  return 1;
}

/* The newest force to take that came since the last call, into *force;
 * returns 0 when none did. */
static int take_force(trephine_bridge_shm* shm, trephine_bridge_udp* socket, const trephine_bridge_address* simulation,
                      uint64_t* seen_writes, trephine_bridge_stream* stream, uint64_t now, trephine_bridge_force* force) {
  unsigned char in[128];
  trephine_bridge_force candidate;
  if (shm) {
    const uint64_t writes = trephine_bridge_shm_force_writes(shm);
    if (writes == *seen_writes || !trephine_bridge_shm_read_force(shm, in)) return 0;
    *seen_writes = writes;
    if (trephine_bridge_decode_force(in, TREPHINE_BRIDGE_FORCE_SIZE, &candidate) != TREPHINE_BRIDGE_OK ||
        !take_if_due(stream, &candidate, now))
      return 0;
    *force = candidate;
    return 1;
  }
  /* Every datagram that waits (a few at most a tick); the newest to take wins. */
  int have = 0;
  trephine_bridge_address from;
  long size;
  for (int k = 0; k < 64 && (size = trephine_bridge_udp_receive(socket, in, sizeof in, &from)) >= 0; ++k)
    if (trephine_bridge_address_equal(&from, simulation) &&
        trephine_bridge_decode_force(in, (size_t)size, &candidate) == TREPHINE_BRIDGE_OK &&
        take_if_due(stream, &candidate, now)) {
      *force = candidate;
      have = 1;
    }
  return have;
}

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? atof(argv[1]) : 5.0;
  const int udp = argc > 4 && strcmp(argv[2], "udp") == 0;
  trephine_bridge_shm* shm = NULL;
  trephine_bridge_udp* socket = NULL;
  trephine_bridge_address simulation;
  int error = 0;
  if (udp) {
    trephine_bridge_address local;
    trephine_bridge_address_parse("127.0.0.1", 0, &local);
    if (trephine_bridge_address_parse(argv[3], (uint16_t)atoi(argv[4]), &simulation) != 0 ||
        !(socket = trephine_bridge_udp_open(&local, &error))) {
      fprintf(stderr, "trephine_device_example: cannot reach %s:%s (%s)\n", argv[3], argv[4], strerror(error));
      return 1;
    }
  } else if (!(shm = trephine_bridge_shm_open("/trephine-bridge", 1, &error))) {
    fprintf(stderr, "trephine_device_example: cannot open /trephine-bridge (%s)\n", strerror(error));
    return 1;
  }

  trephine_bridge_watchdog watchdog;
  trephine_bridge_watchdog_init(&watchdog, 0.02, 0.02);
  /* This program's session, and the simulation's it takes forces of: a
   * simulation started again is heard once the earlier one was quiet for
   * the watchdog's 20 ms. */
  const uint64_t session = trephine_bridge_new_session();
  trephine_bridge_stream forces_stream;
  trephine_bridge_stream_init(&forces_stream, 0.02, 0);
  trephine_bridge_force latest;
  memset(&latest, 0, sizeof latest);
  /* A force left in the shared memory by an earlier run is not news. */
  uint64_t sequence = 0, sent_at = 0, round_trip = 0, seen_forces = shm ? trephine_bridge_shm_force_writes(shm) : 0;
  int answered = 0;
  unsigned long poses = 0, forces = 0, round_trips = 0;
  double round_trip_max_us = 0, force_max_n = 0;
  const uint64_t start = clock_ns();
  uint64_t next = start;
  while (clock_ns() - start < (uint64_t)(seconds * 1e9)) {
    /* The servo clock: 1 kHz (a real device's SDK calls the loop itself). */
    while (clock_ns() < next) {
    }
    next += 1000000u;
    const uint64_t now = clock_ns();
    /* 1. This tick's pose, with the round trip of the last one answered (0: none). */
    trephine_bridge_pose pose;
    memset(&pose, 0, sizeof pose);
    read_device((double)(now - start) * 1e-9, pose.position_mm, pose.orientation_wxyz, &pose.buttons);
    pose.sequence = ++sequence;
    pose.device_time_ns = now;
    pose.round_trip_ns = answered ? (round_trip > 0xffffffffu ? 0xffffffffu : (uint32_t)round_trip) : 0;
    pose.session = session;
    pose.heard_session = forces_stream.session;
    pose.heard_sequence = forces_stream.sequence;
    unsigned char out[TREPHINE_BRIDGE_POSE_SIZE];
    if (trephine_bridge_encode_pose(&pose, out) != TREPHINE_BRIDGE_OK) {
      fprintf(stderr, "trephine_device_example: the device's pose cannot be sent (not finite, or not a unit quaternion)\n");
      return 1;
    }
    if (shm) {
      trephine_bridge_shm_write_pose(shm, out);
    } else {
      trephine_bridge_udp_send(socket, &simulation, out, sizeof out);
    }
    sent_at = now;
    answered = 0;
    ++poses;

    /* 2. The force that answers it, polled for at most kAwaitNs (the simulation
     * answers within its frame); else the newest force at hand. */
    for (uint64_t t = now; !answered && t - now < kAwaitNs; t = clock_ns()) {
      trephine_bridge_force force;
      if (!take_force(shm, socket, &simulation, &seen_forces, &forces_stream, t, &force)) continue;
      latest = force;
      ++forces;
      trephine_bridge_watchdog_heard(&watchdog, t);
      if (force.answered_sequence == sequence) {
        answered = 1;
        round_trip = t - sent_at;
        ++round_trips;
        if ((double)round_trip * 1e-3 > round_trip_max_us) round_trip_max_us = (double)round_trip * 1e-3;
      }
    }

    /* 3. The force to command: the watchdog's gain, the device's limit. */
    double commanded[3];
    trephine_bridge_watchdog_update(&watchdog, clock_ns(), NULL);
    trephine_bridge_guard_force(&watchdog, latest.force_n, 3.3, commanded);
    command_force(commanded);
    const double magnitude = sqrt(commanded[0] * commanded[0] + commanded[1] * commanded[1] + commanded[2] * commanded[2]);
    if (magnitude > force_max_n) force_max_n = magnitude;
  }
  printf("poses %lu forces %lu round_trips %lu round_trip_max_us %.1f force_max_N %.6f last_force %.6f %.6f %.6f "
         "watchdog_trips %lu simulation_sessions %lu\n",
         poses, forces, round_trips, round_trip_max_us, force_max_n, last_commanded[0], last_commanded[1],
         last_commanded[2], (unsigned long)watchdog.trips, (unsigned long)forces_stream.sessions);
  if (shm) trephine_bridge_shm_close(shm, "/trephine-bridge", 0);
  if (socket) trephine_bridge_udp_close(socket);
  return 0;
}
