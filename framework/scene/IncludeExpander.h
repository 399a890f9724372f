#pragma once
// <Include file="part.xml"/>: replaced by the root element of part.xml, a path
// relative to the including file. Includes nest; cycles, missing files, depth
// beyond 32 and more than 1000 includes in a scene are errors at the include.
#include <filesystem>

#include "framework/core/Diagnostics.h"
#include "framework/scene/XmlTree.h"

namespace trephine {

// Expands every include below `holder` (whose children are the scene's root
// element), read from `sceneFile`.
void expandIncludes(XmlElement& holder, const std::filesystem::path& sceneFile, Diagnostics& diagnostics);

}  // namespace trephine
