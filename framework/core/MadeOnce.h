#pragma once
// What a process makes once and copies after: a value that is costly to make
// and always the same for the same key, such as a phantom meshed or filled
// from its specification (the brain phantom's 22,000 tetrahedra take about
// 2 s to mesh). `trephine study` loads each setting's scene up to three times
// (to describe it, to probe it, to run it), and a test program loads the same
// phantom scene many times; each load after the first copies the value.
//
// It keeps the last `capacity` values of at most `maxBytes` each (a larger
// one is made each time, not held beside the copy the caller keeps).
// Thread-safe: two threads asking at once for a value not yet made may both
// make it; either copy is the same.
#include <cstddef>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

namespace trephine {

template <typename Value>
class MadeOnce {
 public:
  // `bytes`: about how much memory a value holds.
  MadeOnce(size_t capacity, size_t maxBytes, std::function<size_t(const Value&)> bytes)
      : m_capacity(capacity), m_maxBytes(maxBytes), m_bytes(std::move(bytes)) {}

  // The value of `key`: a copy of the one made before, else `make()`'s.
  // Whatever `make` throws reaches the caller, and nothing is kept.
  template <typename Make>
  Value get(const std::string& key, Make&& make) {
    {
      const std::lock_guard lock(m_mutex);
      for (auto it = m_values.begin(); it != m_values.end(); ++it)
        if (it->first == key) {
          m_values.splice(m_values.begin(), m_values, it);  // most recently used first
          return *m_values.front().second;
        }
    }
    Value made = make();
    if (m_capacity > 0 && m_bytes(made) <= m_maxBytes) {
      const std::lock_guard lock(m_mutex);
      std::erase_if(m_values, [&](const auto& kept) { return kept.first == key; });  // another thread's, the same
      m_values.emplace_front(key, std::make_shared<const Value>(made));
      while (m_values.size() > m_capacity) m_values.pop_back();
    }
    return made;
  }

 private:
  const size_t m_capacity, m_maxBytes;
  const std::function<size_t(const Value&)> m_bytes;
  std::mutex m_mutex;
  std::list<std::pair<std::string, std::shared_ptr<const Value>>> m_values;
};

}  // namespace trephine
