#include "framework/core/PluginLoader.h"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <set>
#include <sstream>

#include "framework/core/Registry.h"

namespace trephine {

namespace {

constexpr const char* kPrefix = "trephine_";
constexpr const char* kSuffix = ".so";

std::vector<std::filesystem::path> defaultSearchPath() {
  std::vector<std::filesystem::path> path;
  if (const char* env = std::getenv("TREPHINE_PLUGIN_PATH")) {
    std::stringstream entries(env);
    std::string entry;
    while (std::getline(entries, entry, ':'))
      if (!entry.empty()) path.emplace_back(entry);
  }
  // The program's own tree before the build directory compiled into this
  // library: an installed program must load its installed plugins, not those
  // of the build tree it was installed from. In the build tree both are the same.
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) path.push_back(self.parent_path().parent_path() / "lib" / "trephine" / "plugins");
#ifdef TREPHINE_BUILD_PLUGIN_DIR
  if (path.empty() || path.back() != TREPHINE_BUILD_PLUGIN_DIR) path.emplace_back(TREPHINE_BUILD_PLUGIN_DIR);
#endif
  return path;
}

using RegisterFn = void (*)(PluginRegistrar&);
using VersionFn = int (*)();

}  // namespace

PluginLoader::PluginLoader() : m_searchPath(defaultSearchPath()) {}
PluginLoader::PluginLoader(std::vector<std::filesystem::path> searchPath) : m_searchPath(std::move(searchPath)) {}

std::optional<std::filesystem::path> PluginLoader::locate(const std::string& name) const {
  for (const auto& dir : m_searchPath) {
    const auto candidate = dir / (kPrefix + name + kSuffix);
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec)) return candidate;
  }
  return std::nullopt;
}

std::vector<std::string> PluginLoader::available() const {
  std::set<std::string> names;
  for (const auto& dir : m_searchPath) {
    std::error_code ec;
    for (auto it = std::filesystem::directory_iterator(dir, ec); !ec && it != std::filesystem::directory_iterator();
         it.increment(ec)) {
      const std::string file = it->path().filename().string();
      if (file.starts_with(kPrefix) && file.ends_with(kSuffix) && file.size() > 12)
        names.insert(file.substr(9, file.size() - 9 - 3));
    }
  }
  return {names.begin(), names.end()};
}

std::optional<std::string> PluginLoader::load(const std::string& name, Registry& registry) {
  const auto file = locate(name);
  if (!file) {
    std::string searched;
    for (const auto& dir : m_searchPath) searched += (searched.empty() ? "" : ":") + dir.string();
    return "plugin '" + name + "' not found (searched " + (searched.empty() ? "nothing" : searched) +
           "; set TREPHINE_PLUGIN_PATH to add directories)";
  }
  void*& handle = m_handles[file->string()];
  if (!handle) {
    handle = dlopen(file->c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* reason = dlerror();
      m_handles.erase(file->string());
      return "plugin '" + name + "' failed to load from " + file->string() + ": " + (reason ? reason : "unknown error");
    }
  }
  auto version = reinterpret_cast<VersionFn>(dlsym(handle, "trephine_plugin_api_version"));
  auto registerPlugin = reinterpret_cast<RegisterFn>(dlsym(handle, "trephine_register_plugin"));
  if (!version || !registerPlugin)
    return "plugin '" + name + "' (" + file->string() + ") has no trephine_register_plugin entry point";
  if (version() != TREPHINE_PLUGIN_API_VERSION)
    return "plugin '" + name + "' was built for plugin API " + std::to_string(version()) + ", this program has " +
           std::to_string(TREPHINE_PLUGIN_API_VERSION) + "; rebuild it";
  PluginRegistrar registrar(registry, name);
  registerPlugin(registrar);
  if (!registrar.errors().empty()) {
    std::string message;
    for (const auto& e : registrar.errors()) message += (message.empty() ? "" : "; ") + e;
    return message;
  }
  return std::nullopt;
}

}  // namespace trephine
