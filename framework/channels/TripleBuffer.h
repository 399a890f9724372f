#pragma once
// Latest-value channel between one writer thread and one reader thread.
//
// Three slots: the writer owns one, the reader owns one, the third is the
// hand-over slot. Publishing swaps the writer's slot with the hand-over slot;
// reading swaps the reader's slot with it when something new was published.
// Neither side ever blocks, allocates or waits for the other, so a 1 kHz haptic
// loop can exchange data with a slower group without being held up.
#include <array>
#include <atomic>
#include <cstdint>
#include <type_traits>

namespace trephine {

template <class T>
class TripleBuffer {
  static_assert(std::is_copy_assignable_v<T>, "channel values are copied into slots");

 public:
  TripleBuffer() = default;
  explicit TripleBuffer(const T& initial) { m_slots.fill(initial); }
  // Sets all three slots; only while neither side is running (initialisation).
  void fillSlots(const T& value) { m_slots.fill(value); }

  // Writer side: fill the slot returned by writeSlot(), then publish().
  T& writeSlot() { return m_slots[m_writeIndex]; }
  void publish() {
    const uint8_t previous = m_handover.exchange(m_writeIndex | kFresh, std::memory_order_acq_rel);
    m_writeIndex = previous & kIndexMask;
  }
  void write(const T& value) {
    writeSlot() = value;
    publish();
  }

  // Reader side: fetch() takes the newest published value if there is one and
  // returns whether it was new; read() is the reader's current value.
  bool fetch() {
    if ((m_handover.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    const uint8_t previous = m_handover.exchange(m_readIndex, std::memory_order_acq_rel);
    m_readIndex = previous & kIndexMask;
    return true;
  }
  const T& read() const { return m_slots[m_readIndex]; }
  const T& latest() {
    fetch();
    return read();
  }

 private:
  static constexpr uint8_t kIndexMask = 0x3;
  static constexpr uint8_t kFresh = 0x4;

  std::array<T, 3> m_slots{};
  // Cache-line separation keeps the writer's and the reader's private indices
  // from sharing a line with the contended hand-over index.
  alignas(64) std::atomic<uint8_t> m_handover{1};
  alignas(64) uint8_t m_writeIndex = 0;
  alignas(64) uint8_t m_readIndex = 2;
};

}  // namespace trephine
