#pragma once
// Loader directives: the elements of a scene that are not components.
#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

#include "framework/core/Diagnostics.h"
#include "framework/core/Strings.h"
#include "framework/scene/XmlTree.h"

namespace trephine {

inline constexpr std::string_view kNodeTag = "Node";
inline constexpr std::string_view kPluginTag = "RequiredPlugin";
inline constexpr std::string_view kIncludeTag = "Include";

// Reports every attribute of `e` not in `allowed`, with a suggestion.
inline void checkDirectiveAttributes(const XmlElement& e, const std::vector<std::string>& allowed, Diagnostics& d) {
  for (const XmlAttribute& a : e.attributes) {
    if (std::find(allowed.begin(), allowed.end(), a.name) == allowed.end())
      d.error(a.nameAt, "unknown attribute '" + a.name + "' of <" + e.tag + ">" + didYouMean(a.name, allowed));
  }
}

}  // namespace trephine
