/* SPDX-License-Identifier: MIT
 * The Trephine device bridge's packets (trephine_bridge.h). Plain C99. */
#include "trephine_bridge.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

/* Little-endian writes and reads, whatever the machine's byte order. */
static void put_u16(unsigned char* at, uint16_t v) {
  at[0] = (unsigned char)(v & 0xffu);
  at[1] = (unsigned char)(v >> 8);
}
static void put_u32(unsigned char* at, uint32_t v) {
  for (int i = 0; i < 4; ++i) at[i] = (unsigned char)((v >> (8 * i)) & 0xffu);
}
static void put_u64(unsigned char* at, uint64_t v) {
  for (int i = 0; i < 8; ++i) at[i] = (unsigned char)((v >> (8 * i)) & 0xffu);
}
static void put_f64(unsigned char* at, double v) {
  uint64_t bits;
  memcpy(&bits, &v, sizeof bits); /* IEEE 754 binary64 */
  put_u64(at, bits);
}
static uint16_t get_u16(const unsigned char* at) { return (uint16_t)(at[0] | (at[1] << 8)); }
static uint32_t get_u32(const unsigned char* at) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= (uint32_t)at[i] << (8 * i);
  return v;
}
static uint64_t get_u64(const unsigned char* at) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= (uint64_t)at[i] << (8 * i);
  return v;
}
static double get_f64(const unsigned char* at) {
  const uint64_t bits = get_u64(at);
  double v;
  memcpy(&v, &bits, sizeof v);
  return v;
}

static trephine_bridge_status check_pose(const trephine_bridge_pose* p) {
  double norm2 = 0;
  if (p->session == 0) return TREPHINE_BRIDGE_NO_SESSION;
  for (int i = 0; i < 3; ++i)
    if (!isfinite(p->position_mm[i])) return TREPHINE_BRIDGE_NOT_FINITE;
  for (int i = 0; i < 4; ++i) {
    if (!isfinite(p->orientation_wxyz[i])) return TREPHINE_BRIDGE_NOT_FINITE;
    norm2 += p->orientation_wxyz[i] * p->orientation_wxyz[i];
  }
  for (int i = 0; i < 3; ++i)
    if (fabs(p->position_mm[i]) > TREPHINE_BRIDGE_MAX_POSITION_MM) return TREPHINE_BRIDGE_OUT_OF_RANGE;
  if (fabs(sqrt(norm2) - 1.0) > TREPHINE_BRIDGE_UNIT_TOLERANCE) return TREPHINE_BRIDGE_NOT_UNIT;
  return TREPHINE_BRIDGE_OK;
}

static trephine_bridge_status check_force(const trephine_bridge_force* f) {
  if (f->session == 0) return TREPHINE_BRIDGE_NO_SESSION;
  for (int i = 0; i < 3; ++i)
    if (!isfinite(f->force_n[i])) return TREPHINE_BRIDGE_NOT_FINITE;
  for (int i = 0; i < 3; ++i)
    if (fabs(f->force_n[i]) > TREPHINE_BRIDGE_MAX_FORCE_N) return TREPHINE_BRIDGE_OUT_OF_RANGE;
  return TREPHINE_BRIDGE_OK;
}

static void put_header(unsigned char* out, uint16_t kind, uint64_t sequence) {
  put_u32(out, TREPHINE_BRIDGE_MAGIC);
  put_u16(out + 4, TREPHINE_BRIDGE_VERSION);
  put_u16(out + 6, kind);
  put_u64(out + 8, sequence);
}

static trephine_bridge_status check_header(const unsigned char* in, size_t size, size_t expected, uint16_t kind) {
  if (size < 8) return TREPHINE_BRIDGE_WRONG_SIZE;
  if (get_u32(in) != TREPHINE_BRIDGE_MAGIC) return TREPHINE_BRIDGE_BAD_MAGIC;
  if (get_u16(in + 4) != TREPHINE_BRIDGE_VERSION) return TREPHINE_BRIDGE_BAD_VERSION;
  if (get_u16(in + 6) != kind) return TREPHINE_BRIDGE_BAD_KIND;
  if (size != expected) return TREPHINE_BRIDGE_WRONG_SIZE;
  return TREPHINE_BRIDGE_OK;
}

trephine_bridge_status trephine_bridge_encode_pose(const trephine_bridge_pose* pose, unsigned char* out) {
  if (!pose || !out) return TREPHINE_BRIDGE_NULL;
  const trephine_bridge_status status = check_pose(pose);
  if (status != TREPHINE_BRIDGE_OK) return status;
  put_header(out, TREPHINE_BRIDGE_KIND_POSE, pose->sequence);
  put_u64(out + 16, pose->device_time_ns);
  for (int i = 0; i < 3; ++i) put_f64(out + 24 + 8 * i, pose->position_mm[i]);
  for (int i = 0; i < 4; ++i) put_f64(out + 48 + 8 * i, pose->orientation_wxyz[i]);
  put_u32(out + 80, pose->buttons);
  put_u32(out + 84, pose->round_trip_ns);
  put_u64(out + 88, pose->session);
  put_u64(out + 96, pose->heard_session);
  put_u64(out + 104, pose->heard_sequence);
  return TREPHINE_BRIDGE_OK;
}

trephine_bridge_status trephine_bridge_encode_force(const trephine_bridge_force* force, unsigned char* out) {
  if (!force || !out) return TREPHINE_BRIDGE_NULL;
  const trephine_bridge_status status = check_force(force);
  if (status != TREPHINE_BRIDGE_OK) return status;
  put_header(out, TREPHINE_BRIDGE_KIND_FORCE, force->sequence);
  put_u64(out + 16, force->answered_sequence);
  put_u64(out + 24, force->answered_device_time_ns);
  put_u64(out + 32, force->simulation_time_ns);
  for (int i = 0; i < 3; ++i) put_f64(out + 40 + 8 * i, force->force_n[i]);
  put_u32(out + 64, force->flags);
  put_u32(out + 68, 0);
  put_u64(out + 72, force->session);
  return TREPHINE_BRIDGE_OK;
}

trephine_bridge_status trephine_bridge_decode_pose(const unsigned char* in, size_t size, trephine_bridge_pose* out) {
  if (!in || !out) return TREPHINE_BRIDGE_NULL;
  trephine_bridge_status status = check_header(in, size, TREPHINE_BRIDGE_POSE_SIZE, TREPHINE_BRIDGE_KIND_POSE);
  if (status != TREPHINE_BRIDGE_OK) return status;
  trephine_bridge_pose pose;
  pose.sequence = get_u64(in + 8);
  pose.device_time_ns = get_u64(in + 16);
  for (int i = 0; i < 3; ++i) pose.position_mm[i] = get_f64(in + 24 + 8 * i);
  for (int i = 0; i < 4; ++i) pose.orientation_wxyz[i] = get_f64(in + 48 + 8 * i);
  pose.buttons = get_u32(in + 80);
  pose.round_trip_ns = get_u32(in + 84);
  pose.session = get_u64(in + 88);
  pose.heard_session = get_u64(in + 96);
  pose.heard_sequence = get_u64(in + 104);
  status = check_pose(&pose);
  if (status == TREPHINE_BRIDGE_OK) *out = pose;
  return status;
}

trephine_bridge_status trephine_bridge_decode_force(const unsigned char* in, size_t size, trephine_bridge_force* out) {
  if (!in || !out) return TREPHINE_BRIDGE_NULL;
  trephine_bridge_status status = check_header(in, size, TREPHINE_BRIDGE_FORCE_SIZE, TREPHINE_BRIDGE_KIND_FORCE);
  if (status != TREPHINE_BRIDGE_OK) return status;
  if (get_u32(in + 68) != 0) return TREPHINE_BRIDGE_RESERVED_SET;
  trephine_bridge_force force;
  force.sequence = get_u64(in + 8);
  force.answered_sequence = get_u64(in + 16);
  force.answered_device_time_ns = get_u64(in + 24);
  force.simulation_time_ns = get_u64(in + 32);
  for (int i = 0; i < 3; ++i) force.force_n[i] = get_f64(in + 40 + 8 * i);
  force.flags = get_u32(in + 64);
  force.session = get_u64(in + 72);
  status = check_force(&force);
  if (status == TREPHINE_BRIDGE_OK) *out = force;
  return status;
}

const char* trephine_bridge_status_text(trephine_bridge_status status) {
  switch (status) {
    case TREPHINE_BRIDGE_OK: return "ok";
    case TREPHINE_BRIDGE_WRONG_SIZE: return "not the packet's size";
    case TREPHINE_BRIDGE_BAD_MAGIC: return "not a device bridge packet (magic)";
    case TREPHINE_BRIDGE_BAD_VERSION: return "another version of the device bridge";
    case TREPHINE_BRIDGE_BAD_KIND: return "another kind of packet";
    case TREPHINE_BRIDGE_NOT_FINITE: return "a value that is not a finite number";
    case TREPHINE_BRIDGE_OUT_OF_RANGE: return "a position beyond 10 m or a force beyond 1000 N";
    case TREPHINE_BRIDGE_NOT_UNIT: return "an orientation that is not a unit quaternion";
    case TREPHINE_BRIDGE_RESERVED_SET: return "a reserved field that is not zero";
    case TREPHINE_BRIDGE_NULL: return "a null pointer";
    case TREPHINE_BRIDGE_NO_SESSION: return "a session of 0 (a sender picks a random non-zero one)";
  }
  return "an unknown status";
}

int trephine_bridge_is_newer(uint64_t last, uint64_t next) {
  /* Serial-number arithmetic: the difference as a two's complement number. */
  const uint64_t difference = next - last;
  return difference != 0 && difference < (UINT64_C(1) << 63);
}

/* SplitMix64's finaliser: spreads every bit of its input over the output. */
static uint64_t mix(uint64_t z) {
  z += UINT64_C(0x9E3779B97F4A7C15);
  z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
  z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
  return z ^ (z >> 31);
}

uint64_t trephine_bridge_new_session(void) {
  static uint64_t calls;
  uint64_t random = 0;
  FILE* source = fopen("/dev/urandom", "rb");
  if (source) {
    if (fread(&random, sizeof random, 1, source) != 1) random = 0;
    fclose(source);
  }
  const uint64_t local = (uint64_t)(uintptr_t)&calls;
  uint64_t session = mix(random ^ mix((uint64_t)time(NULL) ^ ((uint64_t)clock() << 20) ^ local ^ ++calls));
  return session ? session : 1;
}

void trephine_bridge_stream_init(trephine_bridge_stream* stream, double quiet_s, double max_rate_hz) {
  memset(stream, 0, sizeof *stream);
  stream->quiet_ns = quiet_s > 0 ? (uint64_t)(quiet_s * 1e9) : 0;
  stream->max_rate_hz = max_rate_hz > 0 ? max_rate_hz : 100000.0;
}

/* A sender may skip this many sequences whatever the time (a few packets
 * lost, or a shared memory slot written several times between two reads). */
#define TREPHINE_BRIDGE_SEQUENCE_SLACK 64u

trephine_bridge_verdict trephine_bridge_stream_judge(const trephine_bridge_stream* stream, uint64_t session,
                                                     uint64_t sequence, uint64_t now_ns) {
  const uint64_t quiet = now_ns > stream->taken_ns ? now_ns - stream->taken_ns : 0;
  if (session != stream->session)
    return stream->session == 0 || quiet >= stream->quiet_ns ? TREPHINE_BRIDGE_NEW_SESSION
                                                             : TREPHINE_BRIDGE_OTHER_SESSION;
  if (!trephine_bridge_is_newer(stream->sequence, sequence)) return TREPHINE_BRIDGE_STALE;
  const double explained = (double)TREPHINE_BRIDGE_SEQUENCE_SLACK + (double)quiet * 1e-9 * stream->max_rate_hz;
  if ((double)(sequence - stream->sequence) > explained) return TREPHINE_BRIDGE_TOO_FAR_AHEAD;
  return TREPHINE_BRIDGE_TAKE;
}

void trephine_bridge_stream_take(trephine_bridge_stream* stream, uint64_t session, uint64_t sequence, uint64_t now_ns) {
  if (session != stream->session) ++stream->sessions;
  stream->session = session;
  stream->sequence = sequence;
  stream->taken_ns = now_ns;
}
