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
class CollisionBackend;

struct ComponentEntry {
  std::string type;     // XML tag, e.g. "ScriptedDevice"
  std::string plugin;   // "core" for the framework's own components
  std::string summary;  // one line for the reference
  std::function<std::unique_ptr<Component>()> create;
};

// A collision back-end for one kind of target (the target's component type).
struct BackendEntry {
  std::string kind;     // target component type, e.g. "VoxelSkull"
  std::string name;     // the value of the target's `backend` field, e.g. "native"
  std::string plugin;   // "core" for the framework's own
  std::string summary;  // one line for the reference
  std::function<std::unique_ptr<CollisionBackend>()> create;
};

// Back-ends of this kind are triangle engines (TriangleEngine,
// framework/geometry/TriangleEngine.h): libraries that query any closed
// triangle surface, for every kind of target that registers an adapter.
inline constexpr std::string_view kTriangleEngineKind = "TriangleEngine";

// How a kind of target (its component type) puts a triangle engine to use:
// `adapt` takes a new engine and returns the target's back-end over it. With
// an adapter, every engine is also a back-end of that kind, under its own name.
struct EngineAdapterEntry {
  std::string kind;    // target component type, e.g. "VoxelSkull"
  std::string plugin;  // filled in by the registrar
  std::function<std::unique_ptr<CollisionBackend>(std::unique_ptr<CollisionBackend> engine)> adapt;
};

// Generated data a plugin can write to a file (`trephine phantom SPEC --out
// FILE`): the phantoms its components also read as file="phantom:SPEC". The
// output file's suffix picks the writer (the same phantom name, "cube", is a
// volume in a .mha and a tetrahedral mesh in a .mesh).
struct PhantomWriterEntry {
  std::string kind;                   // what it writes, for messages: "volume", "tetrahedral mesh"
  std::vector<std::string> suffixes;  // the file names it writes end so: ".mha", ".mhd"
  std::string plugin;                 // filled in by the registrar
  std::string help;                   // its phantoms and their keys, one per line
  bool canWriteRaw = false;           // takes --raw (uncompressed output)
  // Writes phantom `specification` to `file` and returns a one-line
  // description of what it wrote; throws std::exception (the specification
  // or the file is wrong).
  std::function<std::string(const std::string& specification, const std::string& file, bool raw)> write;
};

// An object one plugin provides for the others to use through an interface
// of the framework (the tetrahedral mesher), found by the interface's name:
// plugins never link each other's code, nor cast a type of another module.
struct ServiceEntry {
  std::string interface;        // T::kTypeName of the interface
  std::string plugin;           // filled in by the registrar
  std::shared_ptr<void> object;  // points at the T part of the object
};

class Registry {
 public:
  // Adds an entry. Returns an error naming both providers when the type is already registered.
  std::optional<std::string> add(ComponentEntry entry);

  const ComponentEntry* find(std::string_view type) const;
  std::vector<std::string> typeNames() const;
  std::vector<const ComponentEntry*> entries() const;  // sorted by type name
  std::unique_ptr<Component> create(std::string_view type) const;

  // Adds a back-end. Returns an error naming both providers when the kind
  // already has a back-end of that name.
  std::optional<std::string> addBackend(BackendEntry entry);
  // The back-end of that name for `kind`: its own, or a triangle engine when
  // `kind` has an engine adapter.
  const BackendEntry* findBackend(std::string_view kind, std::string_view name) const;
  // Names of the back-ends of `kind` (the engines too when it has an adapter), sorted.
  std::vector<std::string> backendNames(std::string_view kind) const;
  std::vector<const BackendEntry*> backends() const;  // sorted by kind, then name
  // A new back-end, or null when none of that name is registered for `kind`
  // (an engine comes inside the kind's adapter; throws, naming both plugins,
  // when the adapter cannot use the engine).
  std::unique_ptr<CollisionBackend> createBackend(std::string_view kind, std::string_view name) const;
  // Returns an error naming both plugins when the kind already has an adapter.
  std::optional<std::string> addEngineAdapter(EngineAdapterEntry entry);

  // Returns an error naming both plugins when a suffix is already taken.
  std::optional<std::string> addPhantomWriter(PhantomWriterEntry entry);
  // The writer for a file of that name (by its suffix), or null.
  const PhantomWriterEntry* phantomWriterFor(std::string_view fileName) const;
  const std::vector<PhantomWriterEntry>& phantomWriters() const { return m_phantomWriters; }

  // Returns an error naming both plugins when the interface is already provided.
  std::optional<std::string> addService(ServiceEntry entry);
  const ServiceEntry* findService(std::string_view interface) const;
  // The provider of interface T (declaring kTypeName), or null.
  template <class T>
  T* service() const {
    const ServiceEntry* entry = findService(T::kTypeName);
    return entry ? static_cast<T*>(entry->object.get()) : nullptr;
  }

 private:
  std::map<std::string, ComponentEntry, std::less<>> m_entries;
  const BackendEntry* findOwnBackend(std::string_view kind, std::string_view name) const;
  const EngineAdapterEntry* findEngineAdapter(std::string_view kind) const;
  std::map<std::pair<std::string, std::string>, BackendEntry> m_backends;
  std::map<std::string, EngineAdapterEntry, std::less<>> m_engineAdapters;
  std::vector<PhantomWriterEntry> m_phantomWriters;
  std::map<std::string, ServiceEntry, std::less<>> m_services;
};

// Handed to a plugin's registration function.
class PluginRegistrar {
 public:
  PluginRegistrar(Registry& registry, std::string plugin) : m_registry(registry), m_plugin(std::move(plugin)) {}

  template <class T>
  void add(std::string_view type, std::string_view summary) {
    addEntry({std::string(type), m_plugin, std::string(summary), [] { return std::unique_ptr<Component>(new T()); }});
  }

  // A collision back-end named `name` for targets of type `kind` (T derives
  // from that kind's query interface).
  template <class T>
  void addBackend(std::string_view kind, std::string_view name, std::string_view summary) {
    addBackendEntry({std::string(kind), std::string(name), m_plugin, std::string(summary),
                     [] { return std::unique_ptr<CollisionBackend>(new T()); }});
  }

  // A triangle engine (T derives from TriangleEngine), a back-end of every
  // kind of target with an engine adapter.
  template <class T>
  void addTriangleEngine(std::string_view name, std::string_view summary) {
    addBackend<T>(kTriangleEngineKind, name, summary);
  }
  // How targets of type `kind` use a triangle engine: `adapt` takes a new
  // engine (a TriangleEngine) and returns the target's back-end over it.
  void addEngineAdapter(std::string_view kind,
                        std::function<std::unique_ptr<CollisionBackend>(std::unique_ptr<CollisionBackend>)> adapt) {
    addEngineAdapterEntry({std::string(kind), m_plugin, std::move(adapt)});
  }

  void addPhantomWriter(PhantomWriterEntry entry);
  // `object` as the provider of interface T (T declares kTypeName).
  template <class T, class Implementation>
  void addService(std::shared_ptr<Implementation> object) {
    addServiceEntry({std::string(T::kTypeName), m_plugin, std::static_pointer_cast<T>(std::move(object))});
  }

  const std::string& plugin() const { return m_plugin; }
  const std::vector<std::string>& errors() const { return m_errors; }

 private:
  void addEntry(ComponentEntry entry);
  void addBackendEntry(BackendEntry entry);
  void addEngineAdapterEntry(EngineAdapterEntry entry);
  void addServiceEntry(ServiceEntry entry);
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
