#include "framework/core/BackendBinding.h"

#include <stdexcept>

namespace trephine {

void throwBackendFailure(const Component& target, const Field<std::string>& field, const std::exception& e) {
  throw std::runtime_error("collision back-end \"" + field.value() + "\" of " + target.path() + " failed: " + e.what());
}

}  // namespace trephine
