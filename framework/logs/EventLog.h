#pragma once
// Run-time events (a rejected device sample, a deadline miss, a drilled-through
// plate) recorded from any thread without allocating or locking: a fixed array
// and an atomic cursor. Events past the capacity are counted, not stored.
// Each entry carries a flag set once it is written, so that a component can
// read the events logged so far while the run goes on (readSince).
#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace trephine {

struct Event {
  double t = 0;                  // s, simulation time
  const char* kind = "";         // static string, e.g. "device_rejected"
  const char* detail = "";       // static string, e.g. "non_finite"
  const void* source = nullptr;  // the component that logged it (resolved to a path when written)
  double value = 0;              // optional figure, unit given by the kind
  // Optional place (mm, world frame), e.g. where a drill broke through; NaN when none.
  std::array<double, 3> position{std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0};
  bool hasPosition() const { return position[0] == position[0]; }
};

class EventLog {
 public:
  explicit EventLog(size_t capacity = 4096)
      : m_events(capacity), m_written(std::make_unique<std::atomic<bool>[]>(capacity)) {}

  void log(double t, const char* kind, const char* detail, const void* source, double value = 0) {
    store(Event{t, kind, detail, source, value});
  }
  void log(double t, const char* kind, const char* detail, const void* source, double value,
           const std::array<double, 3>& position) {
    store(Event{t, kind, detail, source, value, position});
  }

  // While the run goes on, from any thread: calls f(event) for the events
  // from position `from` on, in order, up to the first one still being
  // written, and returns the position to read from next. Lock- and
  // allocation-free.
  template <class F>
  size_t readSince(size_t from, F&& f) const {
    const size_t end = std::min(m_next.load(std::memory_order_acquire), m_events.size());
    size_t i = from;
    for (; i < end && m_written[i].load(std::memory_order_acquire); ++i) f(m_events[i]);
    return i;
  }

  // Read after the logging threads have stopped.
  size_t size() const { return std::min(m_next.load(), m_events.size()); }
  size_t dropped() const { return m_next.load() > m_events.size() ? m_next.load() - m_events.size() : 0; }
  const Event& operator[](size_t i) const { return m_events[i]; }

 private:
  void store(const Event& event) {
    const size_t index = m_next.fetch_add(1, std::memory_order_relaxed);
    if (index >= m_events.size()) return;
    m_events[index] = event;
    m_written[index].store(true, std::memory_order_release);
  }

  std::vector<Event> m_events;
  std::unique_ptr<std::atomic<bool>[]> m_written;  // per entry: its event is complete
  std::atomic<size_t> m_next{0};
};

}  // namespace trephine
