#pragma once
// The scheduler-owned set of channels. A channel is named by its publisher
// component and a short name ("force"); subscribers get their own reader.
// Created during initialisation only.
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "framework/channels/Channel.h"
#include "framework/core/Component.h"

namespace trephine {

class ChannelHub {
 public:
  // The channel `publisher` writes to under `name`. Throws when the name is
  // already used with another value type.
  template <class T>
  Channel<T>& publish(const Component& publisher, const std::string& name) {
    Channel<T>& channel = getOrCreate<T>(publisher, name);
    channel.hasPublisher = true;
    return channel;
  }

  // A reader of the channel `publisher` writes under `name`.
  template <class T>
  ChannelReader<T> subscribe(const Component& publisher, const std::string& name) {
    return getOrCreate<T>(publisher, name).addReader();
  }

  // Whether `publisher` has published a channel under `name` (so far: call it
  // from a component initialised after the publisher).
  bool published(const Component& publisher, const std::string& name) const {
    const auto at = m_channels.find({&publisher, name});
    return at != m_channels.end() && at->second->hasPublisher;
  }

  // "component/name" of every channel that has readers but nobody publishing.
  std::vector<std::string> unpublished() const {
    std::vector<std::string> names;
    for (const auto& [key, channel] : m_channels)
      if (!channel->hasPublisher) names.push_back(key.first->path() + ":" + key.second);
    return names;
  }

  size_t size() const { return m_channels.size(); }

 private:
  template <class T>
  Channel<T>& getOrCreate(const Component& publisher, const std::string& name) {
    auto& slot = m_channels[{&publisher, name}];
    if (!slot) slot = std::make_unique<Channel<T>>();
    auto* typed = dynamic_cast<Channel<T>*>(slot.get());
    if (!typed)
      throw std::runtime_error("channel '" + name + "' of " + publisher.path() + " carries another value type");
    return *typed;
  }

  std::map<std::pair<const Component*, std::string>, std::unique_ptr<ChannelBase>> m_channels;
};

}  // namespace trephine
