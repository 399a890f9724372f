/* SPDX-License-Identifier: MIT
 * The device bridge over shared memory (trephine_bridge_shm.h). C11. */
#define _POSIX_C_SOURCE 200809L
#include "trephine_bridge_shm.h"

#include <errno.h>
#include <fcntl.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <signal.h>
#include <unistd.h>

#define POSE_WORDS ((TREPHINE_BRIDGE_POSE_SIZE + 7u) / 8u)
#define FORCE_WORDS ((TREPHINE_BRIDGE_FORCE_SIZE + 7u) / 8u)

/* One slot: a sequence (odd while its writer writes; 0: never written) and
 * the packet's bytes as 64-bit words, each read and written atomically (a
 * torn word is impossible; a torn packet is caught by the sequence). */
typedef struct {
  _Atomic uint64_t sequence;
  _Atomic uint64_t words[POSE_WORDS];
} pose_slot;
typedef struct {
  _Atomic uint64_t sequence;
  _Atomic uint64_t words[FORCE_WORDS];
} force_slot;

struct trephine_bridge_shm {
  uint32_t magic;
  uint32_t version;
  pose_slot pose;
  force_slot force;
  _Atomic int64_t simulation; /* the process id of the simulation that claimed it; 0: none */
};

trephine_bridge_shm* trephine_bridge_shm_open(const char* name, int create, int* error) {
  int dummy;
  if (!error) error = &dummy;
  *error = 0;
  if (!name || name[0] != '/' || strchr(name + 1, '/') || strlen(name) < 2) {
    *error = EINVAL;
    return NULL;
  }
  const int fd = shm_open(name, create ? (O_RDWR | O_CREAT) : O_RDWR, S_IRUSR | S_IWUSR);
  if (fd < 0) {
    *error = errno;
    return NULL;
  }
  struct stat st;
  if (fstat(fd, &st) != 0) {
    *error = errno;
    close(fd);
    return NULL;
  }
  const int fresh = st.st_size == 0;
  if (fresh && !create) {
    close(fd);
    *error = EPROTO;
    return NULL;
  }
  if (fresh && ftruncate(fd, (off_t)sizeof(trephine_bridge_shm)) != 0) {
    *error = errno;
    close(fd);
    return NULL;
  }
  if (!fresh && (size_t)st.st_size != sizeof(trephine_bridge_shm)) {
    close(fd);
    *error = EPROTO;
    return NULL;
  }
  void* memory = mmap(NULL, sizeof(trephine_bridge_shm), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  close(fd);
  if (memory == MAP_FAILED) {
    *error = errno;
    return NULL;
  }
  trephine_bridge_shm* shm = (trephine_bridge_shm*)memory;
  if (fresh) {
    /* ftruncate zeroed it: both slots unwritten. */
    shm->version = TREPHINE_BRIDGE_VERSION;
    shm->magic = TREPHINE_BRIDGE_MAGIC;
  } else if (shm->magic != TREPHINE_BRIDGE_MAGIC || shm->version != TREPHINE_BRIDGE_VERSION) {
    munmap(memory, sizeof(trephine_bridge_shm));
    *error = EPROTO;
    return NULL;
  }
  return shm;
}

void trephine_bridge_shm_close(trephine_bridge_shm* shm, const char* name, int unlink) {
  if (shm) munmap(shm, sizeof(trephine_bridge_shm));
  if (unlink && name) shm_unlink(name);
}

static void write_slot(_Atomic uint64_t* sequence, _Atomic uint64_t* words, size_t count, const unsigned char* bytes,
                       size_t size) {
  const uint64_t start = atomic_load_explicit(sequence, memory_order_relaxed);
  atomic_store_explicit(sequence, start + 1, memory_order_relaxed); /* odd: writing */
  atomic_thread_fence(memory_order_release);
  for (size_t w = 0; w < count; ++w) {
    uint64_t word = 0;
    for (size_t b = 0; b < 8 && 8 * w + b < size; ++b) word |= (uint64_t)bytes[8 * w + b] << (8 * b);
    atomic_store_explicit(&words[w], word, memory_order_relaxed);
  }
  atomic_store_explicit(sequence, start + 2, memory_order_release); /* even: whole */
}

static int read_slot(const _Atomic uint64_t* sequence, const _Atomic uint64_t* words, size_t count,
                     unsigned char* bytes, size_t size) {
  const uint64_t before = atomic_load_explicit((_Atomic uint64_t*)sequence, memory_order_acquire);
  if (before == 0 || (before & 1u)) return 0;
  for (size_t w = 0; w < count; ++w) {
    const uint64_t word = atomic_load_explicit((_Atomic uint64_t*)&words[w], memory_order_relaxed);
    for (size_t b = 0; b < 8 && 8 * w + b < size; ++b) bytes[8 * w + b] = (unsigned char)(word >> (8 * b));
  }
  atomic_thread_fence(memory_order_acquire);
  return atomic_load_explicit((_Atomic uint64_t*)sequence, memory_order_relaxed) == before;
}

void trephine_bridge_shm_write_pose(trephine_bridge_shm* shm, const unsigned char packet[TREPHINE_BRIDGE_POSE_SIZE]) {
  write_slot(&shm->pose.sequence, shm->pose.words, POSE_WORDS, packet, TREPHINE_BRIDGE_POSE_SIZE);
}
void trephine_bridge_shm_write_force(trephine_bridge_shm* shm, const unsigned char packet[TREPHINE_BRIDGE_FORCE_SIZE]) {
  write_slot(&shm->force.sequence, shm->force.words, FORCE_WORDS, packet, TREPHINE_BRIDGE_FORCE_SIZE);
}
int trephine_bridge_shm_read_pose(const trephine_bridge_shm* shm, unsigned char out[TREPHINE_BRIDGE_POSE_SIZE]) {
  return read_slot(&shm->pose.sequence, shm->pose.words, POSE_WORDS, out, TREPHINE_BRIDGE_POSE_SIZE);
}
int trephine_bridge_shm_read_force(const trephine_bridge_shm* shm, unsigned char out[TREPHINE_BRIDGE_FORCE_SIZE]) {
  return read_slot(&shm->force.sequence, shm->force.words, FORCE_WORDS, out, TREPHINE_BRIDGE_FORCE_SIZE);
}

uint64_t trephine_bridge_shm_pose_writes(const trephine_bridge_shm* shm) {
  return atomic_load_explicit((_Atomic uint64_t*)&shm->pose.sequence, memory_order_acquire) / 2u;
}
uint64_t trephine_bridge_shm_force_writes(const trephine_bridge_shm* shm) {
  return atomic_load_explicit((_Atomic uint64_t*)&shm->force.sequence, memory_order_acquire) / 2u;
}

long trephine_bridge_shm_claim(trephine_bridge_shm* shm, long pid) {
  for (;;) {
    int64_t holder = atomic_load_explicit(&shm->simulation, memory_order_acquire);
    if (holder == pid) return 0;
    /* A holder still alive keeps it (kill with signal 0 only asks whether it exists). */
    if (holder != 0 && (kill((pid_t)holder, 0) == 0 || errno == EPERM)) return (long)holder;
    if (atomic_compare_exchange_strong_explicit(&shm->simulation, &holder, (int64_t)pid, memory_order_acq_rel,
                                                memory_order_acquire))
      return 0;
  }
}

void trephine_bridge_shm_release(trephine_bridge_shm* shm, long pid) {
  int64_t expected = pid;
  atomic_compare_exchange_strong_explicit(&shm->simulation, &expected, 0, memory_order_acq_rel, memory_order_acquire);
}
