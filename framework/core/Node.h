#pragma once
// A scene node: a named group of components and child nodes.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "framework/core/Component.h"
#include "framework/core/Field.h"
#include "framework/core/FieldOwner.h"

namespace trephine {

class Node final : public FieldOwner {
 public:
  explicit Node(Node* parent = nullptr);
  ~Node() override;

  const std::string& name() const { return d_name.value(); }
  Node* parent() const { return m_parent; }
  std::string path() const;  // "/" for the root, "/tool" for a child

  Node& addChild(std::unique_ptr<Node> child);
  Component& addComponent(std::unique_ptr<Component> component);

  const std::vector<std::unique_ptr<Node>>& children() const { return m_children; }
  const std::vector<std::unique_ptr<Component>>& components() const { return m_components; }

  Node* findChild(std::string_view name) const;
  Component* findComponent(std::string_view name) const;
  // Names of every child node and component (for suggestions).
  std::vector<std::string> memberNames() const;

  // Every component of this subtree in document order (depth first, members in the order
  // they were added, which is the order of the file).
  void collectComponents(std::vector<Component*>& out) const;

  Field<std::string> d_name{this, "name", "", {.help = "Name of the node, unique among its siblings"}};
  EnumField d_units{this, "units", {"mm"}, "mm", {.help = "Length unit of the scene (millimetres only)"}};

 private:
  struct Member {
    bool isComponent;
    size_t index;
  };
  Node* m_parent;
  std::vector<std::unique_ptr<Node>> m_children;
  std::vector<std::unique_ptr<Component>> m_components;
  std::vector<Member> m_order;
};

}  // namespace trephine
