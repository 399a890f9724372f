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

#include "framework/core/CollisionBackend.h"
#include "framework/core/Component.h"
#include "framework/core/Field.h"
#include "framework/core/Lifecycle.h"

namespace trephine {

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
  std::string known;
  for (const std::string& name : context.backendNames(kind)) known += (known.empty() ? "" : ", ") + name;
  context.error(field, "no collision back-end \"" + field.value() + "\" for " + std::string(kind) +
                           " (registered: " + (known.empty() ? "none" : known) +
                           "); if a plugin provides it, add <RequiredPlugin name=\"" + field.value() +
                           "\"/> to the scene");
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
