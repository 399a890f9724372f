#pragma once
// The registry maps a component type name (the XML tag) to its factory and
// the plugin that provides it. It is the single source of truth for what a
// scene may contain and for the generated reference.
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace trephine {

class Component;

struct ComponentEntry {
  std::string type;     // XML tag, e.g. "ScriptedDevice"
  std::string plugin;   // "core" for the framework's own components
  std::string summary;  // one line for the reference
  std::function<std::unique_ptr<Component>()> create;
};

class Registry {
 public:
  // Adds an entry. Returns an error naming both providers when the type is already registered.
  std::optional<std::string> add(ComponentEntry entry);

  const ComponentEntry* find(std::string_view type) const;
  std::vector<std::string> typeNames() const;
  std::vector<const ComponentEntry*> entries() const;  // sorted by type name
  std::unique_ptr<Component> create(std::string_view type) const;

 private:
  std::map<std::string, ComponentEntry, std::less<>> m_entries;
};

// Handed to a plugin's registration function.
class PluginRegistrar {
 public:
  PluginRegistrar(Registry& registry, std::string plugin) : m_registry(registry), m_plugin(std::move(plugin)) {}

  template <class T>
  void add(std::string_view type, std::string_view summary) {
    addEntry({std::string(type), m_plugin, std::string(summary), [] { return std::unique_ptr<Component>(new T()); }});
  }

  const std::string& plugin() const { return m_plugin; }
  const std::vector<std::string>& errors() const { return m_errors; }

 private:
  void addEntry(ComponentEntry entry);
  Registry& m_registry;
  std::string m_plugin;
  std::vector<std::string> m_errors;
};

}  // namespace trephine

// Every plugin defines exactly this function, listing its components:
//
//   TREPHINE_PLUGIN_ENTRY(registrar) {
//     registrar.add<ScriptedDevice>("ScriptedDevice", "Scripted tool motion");
//   }
#define TREPHINE_PLUGIN_API_VERSION 1
#define TREPHINE_PLUGIN_ENTRY(registrar)                                                \
  extern "C" __attribute__((visibility("default"))) int trephine_plugin_api_version() { \
    return TREPHINE_PLUGIN_API_VERSION;                                                 \
  }                                                                                     \
  extern "C" __attribute__((visibility("default"))) void trephine_register_plugin(      \
      ::trephine::PluginRegistrar& registrar)
