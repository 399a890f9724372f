// The key functions of the registry services the runtime declares: their
// type information lives here, once.
#include "framework/runtime/PluginCommands.h"
#include "framework/runtime/RunViewer.h"

namespace trephine {

RunViewer::~RunViewer() = default;
PluginCommands::~PluginCommands() = default;

}  // namespace trephine
