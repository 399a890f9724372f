// The key functions of the framework's interfaces that plugins meet through
// (TREPHINE_INTERFACE): their type information lives in this library alone.
#include "framework/geometry/DeformableMesh.h"

namespace trephine {

DeformableMesh::~DeformableMesh() = default;

}  // namespace trephine
