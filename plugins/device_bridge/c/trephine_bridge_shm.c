/* SPDX-License-Identifier: MIT
 * The device bridge over shared memory (trephine_bridge_shm.h). C11. */
#define _POSIX_C_SOURCE 200809L
#define _DEFAULT_SOURCE /* MAP_ANONYMOUS */
#include "trephine_bridge_shm.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <time.h>
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

/* What the object holds. */
typedef struct {
  uint32_t magic;
  uint32_t version;
  pose_slot pose;
  force_slot force;
  /* The simulation that claimed it: its pid (high 32 bits) and the low 32
   * bits of its start time (clock ticks after boot; 0: unknown); 0: none. */
  _Atomic uint64_t simulation;
} shared_region;

struct trephine_bridge_shm {
  shared_region* region;
  int fd; /* kept open: its size is checked once a tick */
  volatile sig_atomic_t gone;
};

/* The mappings trephine_bridge_shm_guard_truncation protects, for the SIGBUS
 * handler (a fixed table: the handler may not allocate or lock). */
#define GUARDED_MAPPINGS 8
static trephine_bridge_shm* _Atomic guarded[GUARDED_MAPPINGS];
static struct sigaction previous_bus_action;
static atomic_int bus_handler_installed;

/* A fault inside a guarded mapping (the object was truncated between the
 * tick's check and the access): the mapping becomes private zero pages, so
 * the access completes and reads "never written", and the bridge is marked
 * gone. Any other SIGBUS is the previous handler's (by default: the end). */
static void on_bus_error(int signal_number, siginfo_t* info, void* context) {
  char* address = (char*)info->si_addr;
  for (int k = 0; k < GUARDED_MAPPINGS; ++k) {
    trephine_bridge_shm* shm = atomic_load(&guarded[k]);
    if (!shm) continue;
    char* start = (char*)shm->region;
    if (address >= start && address < start + sizeof(shared_region)) {
      mmap(start, sizeof(shared_region), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED, -1, 0);
      shm->gone = 1;
      return;
    }
  }
  if (previous_bus_action.sa_flags & SA_SIGINFO) {
    previous_bus_action.sa_sigaction(signal_number, info, context);
  } else if (previous_bus_action.sa_handler != SIG_DFL && previous_bus_action.sa_handler != SIG_IGN) {
    previous_bus_action.sa_handler(signal_number);
  } else {
    /* Ends the process as it would have: a fault faults again on return, a
     * signal sent (kill -BUS) is raised again. No mapping is guarded now. */
    signal(SIGBUS, SIG_DFL);
    atomic_store(&bus_handler_installed, 0);
    if (info->si_code <= 0) raise(SIGBUS);
  }
}

/* Field 22 of /proc/PID/stat: when the process started, in clock ticks after
 * boot; 0 when unknown (not Linux, or no such process). */
static uint64_t process_start(long pid) {
  char path[64], text[1024];
  snprintf(path, sizeof path, "/proc/%ld/stat", pid);
  FILE* in = fopen(path, "r");
  if (!in) return 0;
  const size_t n = fread(text, 1, sizeof text - 1, in);
  fclose(in);
  text[n] = 0;
  const char* at = strrchr(text, ')'); /* the command name may hold spaces and ')' */
  if (!at) return 0;
  int field = 2;
  for (++at; *at && field < 22; ++at)
    if (*at == ' ') ++field;
  return field == 22 ? strtoull(at, NULL, 10) : 0;
}

trephine_bridge_shm* trephine_bridge_shm_open(const char* name, int create, int* error) {
  int dummy;
  if (!error) error = &dummy;
  *error = 0;
  if (!name || name[0] != '/' || strchr(name + 1, '/') || strlen(name) < 2) {
    *error = EINVAL;
    return NULL;
  }
  /* New and exclusive when it is made here; else an object of this user's alone. */
  int fresh = 0;
  int fd = create ? shm_open(name, O_RDWR | O_CREAT | O_EXCL, S_IRUSR | S_IWUSR) : -1;
  if (fd >= 0) {
    fresh = 1;
  } else if (!create || errno == EEXIST) {
    fd = shm_open(name, O_RDWR, 0);
  }
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
  if (!fresh && (st.st_uid != geteuid() || (st.st_mode & (S_IRWXG | S_IRWXO)) != 0)) {
    close(fd);
    *error = EPERM;
    return NULL;
  }
  if (fresh && ftruncate(fd, (off_t)sizeof(shared_region)) != 0) {
    *error = errno;
    close(fd);
    shm_unlink(name);
    return NULL;
  }
  /* Its maker (the other side, starting at the same moment) may not have
   * sized it yet: a few milliseconds to do so. */
  for (int wait = 0; !fresh && st.st_size == 0 && wait < 50; ++wait) {
    const struct timespec millisecond = {0, 1000000};
    nanosleep(&millisecond, NULL);
    if (fstat(fd, &st) != 0) break;
  }
  if (!fresh && (size_t)st.st_size != sizeof(shared_region)) {
    close(fd);
    *error = EPROTO;
    return NULL;
  }
  void* memory = mmap(NULL, sizeof(shared_region), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  if (memory == MAP_FAILED) {
    *error = errno;
    close(fd);
    return NULL;
  }
  shared_region* region = (shared_region*)memory;
  if (fresh) {
    /* ftruncate zeroed it: both slots unwritten. */
    region->version = TREPHINE_BRIDGE_VERSION;
    atomic_store_explicit((_Atomic uint32_t*)&region->magic, TREPHINE_BRIDGE_MAGIC, memory_order_release);
  } else {
    /* Sized, but its magic perhaps not written yet by its maker. */
    for (int wait = 0;
         wait < 50 && atomic_load_explicit((_Atomic uint32_t*)&region->magic, memory_order_acquire) == 0; ++wait) {
      const struct timespec millisecond = {0, 1000000};
      nanosleep(&millisecond, NULL);
    }
  }
  if (!fresh && (region->magic != TREPHINE_BRIDGE_MAGIC || region->version != TREPHINE_BRIDGE_VERSION)) {
    munmap(memory, sizeof(shared_region));
    close(fd);
    *error = EPROTO;
    return NULL;
  }
  trephine_bridge_shm* shm = (trephine_bridge_shm*)calloc(1, sizeof *shm);
  if (!shm) {
    munmap(memory, sizeof(shared_region));
    close(fd);
    *error = ENOMEM;
    return NULL;
  }
  shm->region = region;
  shm->fd = fd;
  return shm;
}

int trephine_bridge_shm_intact(trephine_bridge_shm* shm) {
  if (shm->gone) return 0;
  struct stat st;
  if (fstat(shm->fd, &st) != 0 || (size_t)st.st_size < sizeof(shared_region)) {
    /* Nothing of it is touched again: the pages beyond its end would fault. */
    shm->gone = 1;
    return 0;
  }
  return 1;
}

int trephine_bridge_shm_guard_truncation(trephine_bridge_shm* shm) {
  if (!atomic_exchange(&bus_handler_installed, 1)) {
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_sigaction = on_bus_error;
    action.sa_flags = SA_SIGINFO;
    sigemptyset(&action.sa_mask);
    if (sigaction(SIGBUS, &action, &previous_bus_action) != 0) {
      atomic_store(&bus_handler_installed, 0);
      return -1;
    }
  }
  for (int k = 0; k < GUARDED_MAPPINGS; ++k) {
    trephine_bridge_shm* none = NULL;
    if (atomic_compare_exchange_strong(&guarded[k], &none, shm)) return 0;
  }
  return -1;
}

void trephine_bridge_shm_close(trephine_bridge_shm* shm, const char* name, int unlink) {
  if (shm) {
    for (int k = 0; k < GUARDED_MAPPINGS; ++k) {
      trephine_bridge_shm* mine = shm;
      atomic_compare_exchange_strong(&guarded[k], &mine, NULL);
    }
    munmap(shm->region, sizeof(shared_region));
    close(shm->fd);
    free(shm);
  }
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
  if (shm->gone) return;
  write_slot(&shm->region->pose.sequence, shm->region->pose.words, POSE_WORDS, packet, TREPHINE_BRIDGE_POSE_SIZE);
}
void trephine_bridge_shm_write_force(trephine_bridge_shm* shm, const unsigned char packet[TREPHINE_BRIDGE_FORCE_SIZE]) {
  if (shm->gone) return;
  write_slot(&shm->region->force.sequence, shm->region->force.words, FORCE_WORDS, packet, TREPHINE_BRIDGE_FORCE_SIZE);
}
int trephine_bridge_shm_read_pose(const trephine_bridge_shm* shm, unsigned char out[TREPHINE_BRIDGE_POSE_SIZE]) {
  if (shm->gone) return 0;
  return read_slot(&shm->region->pose.sequence, shm->region->pose.words, POSE_WORDS, out, TREPHINE_BRIDGE_POSE_SIZE);
}
int trephine_bridge_shm_read_force(const trephine_bridge_shm* shm, unsigned char out[TREPHINE_BRIDGE_FORCE_SIZE]) {
  if (shm->gone) return 0;
  return read_slot(&shm->region->force.sequence, shm->region->force.words, FORCE_WORDS, out,
                   TREPHINE_BRIDGE_FORCE_SIZE);
}

uint64_t trephine_bridge_shm_pose_writes(const trephine_bridge_shm* shm) {
  if (shm->gone) return 0;
  return atomic_load_explicit((_Atomic uint64_t*)&shm->region->pose.sequence, memory_order_acquire) / 2u;
}
uint64_t trephine_bridge_shm_force_writes(const trephine_bridge_shm* shm) {
  if (shm->gone) return 0;
  return atomic_load_explicit((_Atomic uint64_t*)&shm->region->force.sequence, memory_order_acquire) / 2u;
}

/* A claim in one word, so that no one ever sees a pid with another
 * process's start time: the pid in the high half, the low 32 bits of its
 * start time in the low half (0: unknown). */
static uint64_t claim_word(long pid, uint64_t start) { return ((uint64_t)pid << 32) | (start & 0xffffffffu); }

long trephine_bridge_shm_claim(trephine_bridge_shm* shm, long pid) {
  shared_region* region = shm->region;
  const uint64_t mine = claim_word(pid, process_start(pid));
  for (;;) {
    uint64_t holder = atomic_load_explicit(&region->simulation, memory_order_acquire);
    const long holder_pid = (long)(holder >> 32);
    if (holder_pid == pid) return 0;
    /* A holder still alive keeps it (kill with signal 0 only asks whether it
     * exists), unless its pid is another process's now (its start differs). */
    if (holder != 0 && (kill((pid_t)holder_pid, 0) == 0 || errno == EPERM)) {
      const uint64_t claimed = holder & 0xffffffffu, now = process_start(holder_pid) & 0xffffffffu;
      if (claimed == 0 || now == 0 || claimed == now) return holder_pid;
    }
    if (atomic_compare_exchange_strong_explicit(&region->simulation, &holder, mine, memory_order_acq_rel,
                                                memory_order_acquire))
      return 0;
  }
}

void trephine_bridge_shm_release(trephine_bridge_shm* shm, long pid) {
  uint64_t held = atomic_load_explicit(&shm->region->simulation, memory_order_acquire);
  if ((long)(held >> 32) == pid)
    atomic_compare_exchange_strong_explicit(&shm->region->simulation, &held, 0, memory_order_acq_rel,
                                            memory_order_acquire);
}
