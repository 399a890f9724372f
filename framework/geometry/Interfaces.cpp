// The key functions of the framework's interfaces that plugins meet through
// (TREPHINE_INTERFACE): their type information lives in this library alone.
#include "framework/geometry/ContactFrame.h"
#include "framework/geometry/DeformableMesh.h"
#include "framework/geometry/DrillableVolume.h"
#include "framework/geometry/HeldTools.h"
#include "framework/geometry/TriangleEngine.h"

namespace trephine {

ContactFrameMember::~ContactFrameMember() = default;
DeformableMesh::~DeformableMesh() = default;
DrillableVolume::~DrillableVolume() = default;
HeldTools::~HeldTools() = default;
TriangleEngine::~TriangleEngine() = default;

}  // namespace trephine
