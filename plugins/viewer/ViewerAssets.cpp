#include "plugins/viewer/ViewerAssets.h"

#include <cstdlib>
#include <vector>

namespace trephine::viewer {

std::filesystem::path findViewerAssets() {
  namespace fs = std::filesystem;
  std::vector<fs::path> candidates;
  if (const char* set = std::getenv("TREPHINE_VIEWER_ASSETS")) candidates.emplace_back(set);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back(exe.parent_path().parent_path() / "share/trephine/viewer");
  candidates.emplace_back(TREPHINE_VIEWER_BUILD_DIR);
  for (const fs::path& candidate : candidates)
    if (fs::is_regular_file(candidate / "viewer.js", ec) && fs::is_regular_file(candidate / "index.html", ec))
      return candidate;
  return {};
}

}  // namespace trephine::viewer
