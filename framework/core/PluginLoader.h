#pragma once
// Finds and loads plugins: shared libraries named trephine_<name>.so in the
// directories of TREPHINE_PLUGIN_PATH (colon-separated, searched first), then
// <program>/../lib/trephine/plugins, then the build's plugin directory.
// Libraries stay loaded for the life of the process: components created from
// them may outlive any one scene.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace trephine {

class Registry;

class PluginLoader {
 public:
  PluginLoader();  // search path from the environment and the build
  explicit PluginLoader(std::vector<std::filesystem::path> searchPath);

  const std::vector<std::filesystem::path>& searchPath() const { return m_searchPath; }

  // Registers plugin `name`'s components into `registry`. Returns an error
  // (not found, failed to open, missing entry point, duplicate component) or nothing.
  std::optional<std::string> load(const std::string& name, Registry& registry);

  // Names of every plugin found on the search path.
  std::vector<std::string> available() const;
  std::optional<std::filesystem::path> locate(const std::string& name) const;

 private:
  std::vector<std::filesystem::path> m_searchPath;
  std::map<std::string, void*> m_handles;  // by resolved file path
};

}  // namespace trephine
