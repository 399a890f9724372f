#pragma once
// Where the built browser viewer is (index.html and viewer.js): the folder
// TREPHINE_VIEWER_ASSETS names, the installed copy
// (<prefix>/share/trephine/viewer), or the build's; empty when none has it.
#include <filesystem>

namespace trephine::viewer {

std::filesystem::path findViewerAssets();

}  // namespace trephine::viewer
