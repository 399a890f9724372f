#pragma once
// Builds a Scene from XML, strictly: every problem in the file (and its
// includes, and the --set overrides) is collected with its file:line:col, and
// the load fails once at the end. A scene that loads has no errors.
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "framework/core/Diagnostics.h"
#include "framework/core/PluginLoader.h"
#include "framework/core/Registry.h"
#include "framework/scene/Scene.h"

namespace trephine {

class SceneLoader {
 public:
  // `registry` holds the components available without a plugin; plugins named
  // by <RequiredPlugin> are added to it as the scene asks for them.
  SceneLoader(Registry& registry, PluginLoader& plugins) : m_registry(registry), m_plugins(plugins) {}

  // `overrides` are "path.field=value" strings, validated like attributes.
  std::unique_ptr<Scene> loadFile(const std::filesystem::path& file, Diagnostics& diagnostics,
                                  const std::vector<std::string>& overrides = {});
  // `fileName` names the text in messages; includes resolve from its directory.
  std::unique_ptr<Scene> loadString(std::string_view xml, const std::string& fileName, Diagnostics& diagnostics,
                                    const std::vector<std::string>& overrides = {});

 private:
  struct Build;
  std::unique_ptr<Scene> build(struct XmlElement root, const std::filesystem::path& file, Diagnostics& diagnostics,
                               const std::vector<std::string>& overrides);

  Registry& m_registry;
  PluginLoader& m_plugins;
  std::vector<std::string> m_loadedPlugins;
};

}  // namespace trephine
