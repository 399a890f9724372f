#include "framework/scene/ScenePaths.h"

#include <vector>

#include "framework/core/Strings.h"

namespace trephine {

// Resolves "a/b/c" from `start` (or the root when it starts with '/'): the
// leading segments are nodes, the last a component. Reports at `where`.
Component* resolveComponentPath(std::string_view path, Node& start, Node& root, const SourceLocation& where,
                                const std::string& what, Diagnostics& diagnostics,
                                const std::set<std::pair<const Node*, std::string>>* uncreated) {
  Node* node = &start;
  if (path.ends_with('/')) {
    diagnostics.error(where, what + ": a path ends with the name of a component, not with '/'");
    return nullptr;
  }
  if (path.starts_with('/')) {
    node = &root;
    path.remove_prefix(1);
  }
  std::vector<std::string_view> segments;
  size_t begin = 0;
  while (begin <= path.size()) {
    const size_t slash = path.find('/', begin);
    const size_t end = slash == std::string_view::npos ? path.size() : slash;
    segments.push_back(path.substr(begin, end - begin));
    if (slash == std::string_view::npos) break;
    begin = slash + 1;
  }
  for (size_t i = 0; i < segments.size(); ++i) {
    const std::string segment(segments[i]);
    const bool last = i + 1 == segments.size();
    if (segment.empty() || segment == ".") {
      if (last) break;
      continue;
    }
    if (segment == "..") {
      if (!node->parent()) {
        diagnostics.error(where, what + ": '..' goes above the root node");
        return nullptr;
      }
      node = node->parent();
      continue;
    }
    if (last) {
      if (Component* c = node->findComponent(segment)) return c;
      if (uncreated && uncreated->count({node, segment})) return nullptr;
      if (node->findChild(segment)) {
        diagnostics.error(where, what + ": '" + segment + "' is a node, not a component");
        return nullptr;
      }
    } else if (Node* child = node->findChild(segment)) {
      node = child;
      continue;
    }
    diagnostics.error(where, what + ": no " + (last ? "component" : "node") + " '" + segment + "' in node '" +
                                 node->path() + "'" + didYouMean(segment, node->memberNames()));
    return nullptr;
  }
  diagnostics.error(where, what + ": the path names no component");
  return nullptr;
}

// The node at `path` from the root, or nullptr (quietly: the path may name a component).
Node* findNodePath(std::string_view path, Node& root) {
  Node* node = &root;
  while (!path.empty()) {
    const size_t slash = path.find('/');
    const std::string_view segment = path.substr(0, slash);
    path = slash == std::string_view::npos ? std::string_view() : path.substr(slash + 1);
    if (segment.empty() || segment == ".") continue;
    node = segment == ".." ? node->parent() : node->findChild(segment);
    if (!node) return nullptr;
  }
  return node;
}

}  // namespace trephine
