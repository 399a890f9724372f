#pragma once
// Typed links: an attribute whose value is `@path` to another component of a
// given type. Paths are explicit: `@name` is a component of the same node,
// `@../node/name` goes up, `@/node/name` starts at the root. There is no
// implicit search of ancestors.
#include <string>
#include <string_view>

#include "framework/core/Field.h"

namespace trephine {

class Component;

class BaseLink : public BaseField {
 public:
  BaseLink(FieldOwner* owner, std::string_view name, std::string_view targetType, FieldInfo info);

  bool isLink() const override { return true; }
  std::string typeName() const override { return "link<" + m_targetType + ">"; }
  std::string valueText() const override { return m_path.empty() ? "" : "@" + m_path; }
  std::string defaultText() const override { return ""; }

  const std::string& targetType() const { return m_targetType; }
  const std::string& path() const { return m_path; }  // without the leading '@'
  bool hasPath() const { return !m_path.empty(); }

  // Sets the target if it has the right type; returns false otherwise.
  virtual bool bind(Component* target) = 0;
  virtual Component* boundComponent() const = 0;

 protected:
  std::optional<std::string> parseAndStore(std::string_view text, const ParseContext&) override;

 private:
  std::string m_targetType;
  std::string m_path;
};

// T must declare `static constexpr std::string_view kTypeName`, the name shown
// in errors and in the reference ("HapticDevice", "SurfaceTarget", ...). T may
// be a component class or an interface that does not derive from Component
// (a component may implement several interfaces).
template <class T>
class Link final : public BaseLink {
 public:
  Link(FieldOwner* owner, std::string_view name, FieldInfo info) : BaseLink(owner, name, T::kTypeName, info) {}

  T* get() const { return m_target; }
  // The linked component itself (for its path, its channels).
  T* operator->() const { return m_target; }
  T& operator*() const { return *m_target; }
  explicit operator bool() const { return m_target != nullptr; }

  bool bind(Component* target) override;
  Component* boundComponent() const override;

 private:
  T* m_target = nullptr;
  Component* m_component = nullptr;
};

}  // namespace trephine
