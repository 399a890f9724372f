#pragma once
// Every-value channel between one writer thread and one reader thread: a
// fixed ring the writer appends to and the reader drains. Where a triple
// buffer hands over only the latest value (a reader that skips frames never
// sees the others), this one loses nothing while it has room: for changes a
// reader must apply all of (the voxels a drill lowered, for a copy of the
// volume kept elsewhere). Neither side blocks, waits or allocates after
// construction. When the reader falls a whole ring behind, the writer counts
// what it could not store (dropped()) and the reader knows its copy is stale.
#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace trephine {

template <class T>
class ChangeQueue {
 public:
  // Room for `capacity` values (rounded up to a power of two). Allocates.
  explicit ChangeQueue(size_t capacity) : m_slots(std::bit_ceil(std::max<size_t>(capacity, 2))) {
    m_mask = m_slots.size() - 1;
  }
  size_t capacity() const { return m_slots.size(); }

  // Writer side: false (and counted) when the ring is full.
  bool push(const T& value) {
    const uint64_t head = m_head.load(std::memory_order_relaxed);
    if (head - m_tail.load(std::memory_order_acquire) == m_slots.size()) {
      m_dropped.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    m_slots[head & m_mask] = value;
    m_head.store(head + 1, std::memory_order_release);
    return true;
  }

  // Reader side: calls f(value) for every value pushed since the last drain,
  // oldest first; returns how many.
  template <class F>
  size_t drain(F&& f) {
    const uint64_t tail = m_tail.load(std::memory_order_relaxed);
    const uint64_t head = m_head.load(std::memory_order_acquire);
    for (uint64_t i = tail; i != head; ++i) f(m_slots[i & m_mask]);
    m_tail.store(head, std::memory_order_release);
    return size_t(head - tail);
  }
  // Values the writer could not store, since construction (either side).
  uint64_t dropped() const { return m_dropped.load(std::memory_order_relaxed); }

 private:
  std::vector<T> m_slots;
  size_t m_mask = 0;
  // Cache-line separation: the writer's and the reader's cursors.
  alignas(64) std::atomic<uint64_t> m_head{0};
  alignas(64) std::atomic<uint64_t> m_tail{0};
  alignas(64) std::atomic<uint64_t> m_dropped{0};
};

}  // namespace trephine
