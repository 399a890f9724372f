// A plugin that registers a type the haptics plugin also registers, to test
// that the clash is reported with both plugin names.
#include "framework/core/Component.h"
#include "framework/core/Registry.h"

namespace {
class OtherSphereTool final : public trephine::Component {};
}  // namespace

TREPHINE_PLUGIN_ENTRY(registrar) { registrar.add<OtherSphereTool>("SphereTool", "A clashing registration"); }
