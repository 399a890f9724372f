#pragma once
// Paths inside a scene: "name" (in the starting node), "../node/name" (up,
// then down), "/node/name" (from the root). There is no implicit search.
#include <set>
#include <string>
#include <utility>
#include <string_view>

#include "framework/core/Diagnostics.h"
#include "framework/core/Node.h"

namespace trephine {

// The component at `path` from `start` (or the root for "/..."): the leading
// segments are nodes, the last a component. On failure reports at `where`
// (prefixed with `what`, with a suggestion) and returns nullptr.
// A path ending at a name in `uncreated` (a component whose element was already
// reported as invalid) returns nullptr without a second report.
Component* resolveComponentPath(std::string_view path, Node& start, Node& root, const SourceLocation& where,
                                const std::string& what, Diagnostics& diagnostics,
                                const std::set<std::pair<const Node*, std::string>>* uncreated = nullptr);

// The node at `path` from the root, or nullptr without a report (the path may name a component).
Node* findNodePath(std::string_view path, Node& root);

}  // namespace trephine
