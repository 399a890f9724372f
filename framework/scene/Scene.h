#pragma once
// A loaded scene: the node tree, the file it came from and the plugins it loaded.
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "framework/core/Node.h"

namespace trephine {

class Scene {
 public:
  Scene(std::unique_ptr<Node> root, std::filesystem::path file, std::vector<std::string> plugins)
      : m_root(std::move(root)), m_file(std::move(file)), m_plugins(std::move(plugins)) {}

  Node& root() const { return *m_root; }
  const std::filesystem::path& file() const { return m_file; }
  const std::vector<std::string>& plugins() const { return m_plugins; }

  // Every component in document order.
  std::vector<Component*> components() const;
  // "/tool/device" or "tool/device"; nullptr when absent.
  Component* findComponent(std::string_view path) const;

 private:
  std::unique_ptr<Node> m_root;
  std::filesystem::path m_file;
  std::vector<std::string> m_plugins;
};

}  // namespace trephine
