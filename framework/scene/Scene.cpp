#include "framework/scene/Scene.h"

namespace trephine {

std::vector<Component*> Scene::components() const {
  std::vector<Component*> list;
  m_root->collectComponents(list);
  return list;
}

Component* Scene::findComponent(std::string_view path) const {
  if (path.starts_with('/')) path.remove_prefix(1);
  for (Component* c : components()) {
    if (std::string_view(c->path()).substr(1) == path) return c;
  }
  return nullptr;
}

}  // namespace trephine
