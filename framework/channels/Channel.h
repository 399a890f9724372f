#pragma once
// Typed channels owned by the scheduler's hub. A publisher writes one value per
// tick; each subscriber owns its own triple buffer, so any number of readers in
// other rate groups see the latest value without locks. Channels are created
// during initialisation only; after that their set of readers is fixed.
#include <cassert>
#include <memory>
#include <string>
#include <typeindex>
#include <vector>

#include "framework/channels/TripleBuffer.h"

namespace trephine {

template <class T>
class ChannelReader {
 public:
  // Returns true when a value newer than the last fetch arrived.
  bool fetch() { return m_buffer->fetch(); }
  const T& read() const { return m_buffer->read(); }
  const T& latest() { return m_buffer->latest(); }

 private:
  template <class>
  friend class Channel;
  explicit ChannelReader(TripleBuffer<T>* buffer) : m_buffer(buffer) {}
  TripleBuffer<T>* m_buffer;
};

class ChannelBase {
 public:
  virtual ~ChannelBase() = default;
  virtual std::type_index valueType() const = 0;
  bool hasPublisher = false;
};

template <class T>
class Channel final : public ChannelBase {
 public:
  std::type_index valueType() const override { return typeid(T); }

  // Publisher side: copy `value` to every reader's hand-over slot.
  void publish(const T& value) {
    for (auto& buffer : m_buffers) buffer->write(value);
  }

  // Adds a reader. Called during initialisation only (allocates).
  ChannelReader<T> addReader() {
    m_buffers.push_back(m_prototype ? std::make_unique<TripleBuffer<T>>(*m_prototype)
                                    : std::make_unique<TripleBuffer<T>>());
    return ChannelReader<T>(m_buffers.back().get());
  }

  // Fills every slot of every reader, present and future, with `prototype`.
  // For values that own memory (vectors sized to their largest content): a
  // copy into a slot that already holds as much never allocates, so the
  // publisher's loop stays allocation-free. Initialisation only.
  void reserve(const T& prototype) {
    m_prototype = std::make_unique<T>(prototype);
    for (auto& buffer : m_buffers) buffer->fillSlots(prototype);
  }

  size_t readerCount() const { return m_buffers.size(); }

 private:
  std::vector<std::unique_ptr<TripleBuffer<T>>> m_buffers;
  std::unique_ptr<T> m_prototype;
};

}  // namespace trephine
