#pragma once
// Anything a scene element configures: components and nodes. Fields register
// themselves here on construction, in declaration order.
#include <string>
#include <string_view>
#include <vector>

#include "framework/core/Diagnostics.h"

namespace trephine {

class BaseField;

class FieldOwner {
 public:
  FieldOwner() = default;
  FieldOwner(const FieldOwner&) = delete;
  FieldOwner& operator=(const FieldOwner&) = delete;
  virtual ~FieldOwner() = default;

  const std::vector<BaseField*>& fields() const { return m_fields; }
  BaseField* findField(std::string_view name) const;
  std::vector<std::string> fieldNames() const;

  // Where the element that created this object starts in its scene file.
  const SourceLocation& location() const { return m_location; }
  void setLocation(SourceLocation where) { m_location = std::move(where); }

 private:
  friend class BaseField;
  std::vector<BaseField*> m_fields;
  SourceLocation m_location;
};

}  // namespace trephine
