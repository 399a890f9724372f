#include "framework/core/Node.h"

namespace trephine {

Node::Node(Node* parent) : m_parent(parent) {}
Node::~Node() = default;

std::string Node::path() const {
  if (!m_parent) return "/";
  const std::string parentPath = m_parent->path();
  return (parentPath == "/" ? "" : parentPath) + "/" + name();
}

Node& Node::addChild(std::unique_ptr<Node> child) {
  m_order.push_back({false, m_children.size()});
  m_children.push_back(std::move(child));
  return *m_children.back();
}

Component& Node::addComponent(std::unique_ptr<Component> component) {
  m_order.push_back({true, m_components.size()});
  m_components.push_back(std::move(component));
  return *m_components.back();
}

Node* Node::findChild(std::string_view name) const {
  for (const auto& child : m_children)
    if (child->name() == name) return child.get();
  return nullptr;
}

Component* Node::findComponent(std::string_view name) const {
  for (const auto& component : m_components)
    if (component->name() == name) return component.get();
  return nullptr;
}

std::vector<std::string> Node::memberNames() const {
  std::vector<std::string> names;
  for (const auto& child : m_children) names.push_back(child->name());
  for (const auto& component : m_components) names.push_back(component->name());
  return names;
}

void Node::collectComponents(std::vector<Component*>& out) const {
  for (const Member& member : m_order) {
    if (member.isComponent) {
      out.push_back(m_components[member.index].get());
    } else {
      m_children[member.index]->collectComponents(out);
    }
  }
}

}  // namespace trephine
