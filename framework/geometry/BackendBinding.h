#pragma once
// What every target with a `backend` field does with its collision back-end:
// create it from the registry (or say, at the field, what is registered and
// which <RequiredPlugin/> would add it), and call it behind an exception
// boundary, so that a third-party library's exception ends the tick naming
// the target and its back-end (the run then stops with every output written).
#include <exception>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "framework/core/CollisionBackend.h"
#include "framework/core/Component.h"
#include "framework/core/Field.h"
#include "framework/core/Lifecycle.h"

namespace trephine {

// Why no back-end `name` serves targets of type `kind`: the names registered,
// the closest of them or of the installed plugins (a typo), and the
// <RequiredPlugin/> that would load an installed plugin of that name.
std::string missingBackendMessage(std::string_view name, std::string_view kind,
                                  const std::vector<std::string>& registered,
                                  const std::vector<std::string>& installed);

// The back-end `field`'s value names for targets of type `kind`, as the
// target's query interface `Backend`; null, with the error reported at
// `field`, when none is registered under that name (or it is of another kind).
template <class Backend>
std::unique_ptr<Backend> createBackendAt(InitContext& context, const Field<std::string>& field, std::string_view kind) {
  std::unique_ptr<CollisionBackend> created = context.createBackend(kind, field.value());
  if (auto* backend = dynamic_cast<Backend*>(created.get())) {
    created.release();
    return std::unique_ptr<Backend>(backend);
  }
  context.error(field,
                missingBackendMessage(field.value(), kind, context.backendNames(kind), context.installedPlugins()));
  return nullptr;
}

// Rethrows `e` as the failure of the back-end `field` names, of `target`.
[[noreturn]] void throwBackendFailure(const Component& target, const Field<std::string>& field,
                                      const std::exception& e);

// Calls `query` on the back-end `field` names, of `target`. Nothing is paid
// while nothing throws (the message is made in the catch).
template <class Query>
decltype(auto) askBackend(const Component& target, const Field<std::string>& field, Query&& query) {
  try {
    return query();
  } catch (const std::exception& e) {
    throwBackendFailure(target, field, e);
  }
}

}  // namespace trephine
