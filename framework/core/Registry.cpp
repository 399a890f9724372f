#include "framework/core/Registry.h"

#include <algorithm>
#include <stdexcept>

#include "framework/core/CollisionBackend.h"
#include "framework/core/Component.h"

namespace trephine {

std::optional<std::string> Registry::add(ComponentEntry entry) {
  if (const ComponentEntry* existing = find(entry.type)) {
    return "component '" + entry.type + "' is registered by both plugin '" + existing->plugin + "' and plugin '" +
           entry.plugin + "'";
  }
  std::string key = entry.type;
  m_entries.emplace(std::move(key), std::move(entry));
  return std::nullopt;
}

const ComponentEntry* Registry::find(std::string_view type) const {
  const auto it = m_entries.find(type);
  return it == m_entries.end() ? nullptr : &it->second;
}

std::vector<std::string> Registry::typeNames() const {
  std::vector<std::string> names;
  for (const auto& [name, entry] : m_entries) names.push_back(name);
  return names;
}

std::vector<const ComponentEntry*> Registry::entries() const {
  std::vector<const ComponentEntry*> list;
  for (const auto& [name, entry] : m_entries) list.push_back(&entry);
  return list;
}

std::unique_ptr<Component> Registry::create(std::string_view type) const {
  const ComponentEntry* entry = find(type);
  if (!entry) return nullptr;
  auto component = entry->create();
  component->attach(nullptr, entry->type);
  return component;
}

std::optional<std::string> Registry::addBackend(BackendEntry entry) {
  if (const BackendEntry* existing = findOwnBackend(entry.kind, entry.name)) {
    return "back-end '" + entry.name + "' of " + entry.kind + " is registered by both plugin '" + existing->plugin +
           "' and plugin '" + entry.plugin + "'";
  }
  auto key = std::make_pair(entry.kind, entry.name);
  m_backends.emplace(std::move(key), std::move(entry));
  return std::nullopt;
}

const BackendEntry* Registry::findOwnBackend(std::string_view kind, std::string_view name) const {
  const auto it = m_backends.find(std::make_pair(std::string(kind), std::string(name)));
  return it == m_backends.end() ? nullptr : &it->second;
}

const EngineAdapterEntry* Registry::findEngineAdapter(std::string_view kind) const {
  const auto it = m_engineAdapters.find(kind);
  return it == m_engineAdapters.end() ? nullptr : &it->second;
}

const BackendEntry* Registry::findBackend(std::string_view kind, std::string_view name) const {
  if (const BackendEntry* own = findOwnBackend(kind, name)) return own;
  return findEngineAdapter(kind) ? findOwnBackend(kTriangleEngineKind, name) : nullptr;
}

std::vector<std::string> Registry::backendNames(std::string_view kind) const {
  std::vector<std::string> names;
  const bool takesEngines = findEngineAdapter(kind) != nullptr;
  for (const auto& [key, entry] : m_backends)
    if (key.first == kind || (takesEngines && key.first == kTriangleEngineKind && !findOwnBackend(kind, key.second)))
      names.push_back(key.second);
  std::sort(names.begin(), names.end());
  return names;
}

std::optional<std::string> Registry::addEngineAdapter(EngineAdapterEntry entry) {
  if (const EngineAdapterEntry* existing = findEngineAdapter(entry.kind))
    return "the triangle engines' adapter of " + entry.kind + " is registered by both plugin '" + existing->plugin +
           "' and plugin '" + entry.plugin + "'";
  std::string kind = entry.kind;
  m_engineAdapters.emplace(std::move(kind), std::move(entry));
  return std::nullopt;
}

void PluginRegistrar::addEngineAdapterEntry(EngineAdapterEntry entry) {
  if (auto error = m_registry.addEngineAdapter(std::move(entry))) m_errors.push_back(*error);
}

std::vector<const BackendEntry*> Registry::backends() const {
  std::vector<const BackendEntry*> list;
  for (const auto& [key, entry] : m_backends) list.push_back(&entry);
  return list;
}

std::unique_ptr<CollisionBackend> Registry::createBackend(std::string_view kind, std::string_view name) const {
  if (const BackendEntry* own = findOwnBackend(kind, name)) return own->create();
  const EngineAdapterEntry* adapter = findEngineAdapter(kind);
  const BackendEntry* engine = adapter ? findOwnBackend(kTriangleEngineKind, name) : nullptr;
  if (!engine) return nullptr;
  std::unique_ptr<CollisionBackend> adapted = adapter->adapt(engine->create());
  // An engine the adapter cannot take (a plugin's class that is no
  // TriangleEngine) is its plugin's error, not a missing back-end.
  if (!adapted)
    throw std::runtime_error("back-end '" + std::string(name) + "' of plugin '" + engine->plugin +
                             "' is registered as a triangle engine, but " + std::string(kind) +
                             "'s adapter (plugin '" + adapter->plugin + "') cannot use it: it is not a TriangleEngine");
  return adapted;
}

void PluginRegistrar::addBackendEntry(BackendEntry entry) {
  if (auto error = m_registry.addBackend(std::move(entry))) m_errors.push_back(*error);
}

std::optional<std::string> Registry::addPhantomWriter(PhantomWriterEntry entry) {
  // Suffixes of different writers must not end one another (".gz" and
  // ".mesh.gz"), or a file name would not say which writer it is for.
  for (const std::string& suffix : entry.suffixes)
    for (const PhantomWriterEntry& existing : m_phantomWriters)
      for (const std::string& other : existing.suffixes)
        if (suffix.ends_with(other) || other.ends_with(suffix))
          return "phantom files '" + suffix + "' are written by both plugin '" + existing.plugin + "' ('" + other +
                 "') and plugin '" + entry.plugin + "'";
  m_phantomWriters.push_back(std::move(entry));
  return std::nullopt;
}

const PhantomWriterEntry* Registry::phantomWriterFor(std::string_view fileName) const {
  // The longest matching suffix: a writer of .mesh and .mesh.gz gets both.
  const PhantomWriterEntry* found = nullptr;
  size_t longest = 0;
  for (const PhantomWriterEntry& writer : m_phantomWriters)
    for (const std::string& suffix : writer.suffixes)
      if (fileName.size() > suffix.size() && fileName.ends_with(suffix) && suffix.size() > longest)
        found = &writer, longest = suffix.size();
  return found;
}

void PluginRegistrar::addPhantomWriter(PhantomWriterEntry entry) {
  entry.plugin = m_plugin;
  if (auto error = m_registry.addPhantomWriter(std::move(entry))) m_errors.push_back(*error);
}

void PluginRegistrar::addEntry(ComponentEntry entry) {
  if (auto error = m_registry.add(std::move(entry))) m_errors.push_back(*error);
}

std::optional<std::string> Registry::addService(ServiceEntry entry) {
  if (const ServiceEntry* existing = findService(entry.interface))
    return entry.interface + " is provided by plugin '" + existing->plugin + "' and again by plugin '" +
           entry.plugin + "'";
  std::string interface = entry.interface;
  m_services.emplace(std::move(interface), std::move(entry));
  return std::nullopt;
}

const ServiceEntry* Registry::findService(std::string_view interface) const {
  const auto found = m_services.find(interface);
  return found == m_services.end() ? nullptr : &found->second;
}

void PluginRegistrar::addServiceEntry(ServiceEntry entry) {
  if (auto error = m_registry.addService(std::move(entry))) m_errors.push_back(*error);
}

}  // namespace trephine
