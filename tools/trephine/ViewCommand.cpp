#include "tools/trephine/ViewCommand.h"

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <algorithm>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "framework/core/AtomicFile.h"
#include "framework/core/FolderInput.h"
#include "framework/core/OutputFolder.h"
#include "framework/runtime/RunFolder.h"
#include "framework/core/PluginLoader.h"
#include "framework/core/Registry.h"
#include "framework/runtime/RunViewer.h"

namespace trephine::cli {

namespace fs = std::filesystem;

namespace {

// Whether the folder's outputs are whole. A run that is still writing, or was
// killed while writing, left files of one moment each (and, before markers,
// of two runs mixed): viewed only when asked, with a warning.
bool runOutputsUsable(const fs::path& run, bool partialAsked) {
  std::optional<RunMarker> marker;
  try {
    marker = readRunMarker(run);
  } catch (const RunFolderError& e) {
    std::cerr << "trephine view: " << e.what() << "\n";
    return false;
  }
  const RunFolderStatus status = runFolderStatus(marker);
  if (status == RunFolderStatus::kIncomplete)
    std::cerr << "trephine view: note: the run stopped early or lost an output (" << marker->reason
              << "); its files are whole\n";
  if (status != RunFolderStatus::kWriting && status != RunFolderStatus::kKilled) return true;
  const std::string what = status == RunFolderStatus::kWriting
                               ? "a run (process " + std::to_string(marker->pid) + ") is still writing it"
                               : "the run writing it (process " + std::to_string(marker->pid) +
                                     ") stopped without finishing (killed or crashed)";
  if (!partialAsked) {
    std::cerr << "trephine view: " << run.string() << ": " << what
              << ", so its files may be cut off or missing; --partial builds the viewer anyway\n";
    return false;
  }
  std::cerr << "trephine view: warning: " << run.string() << ": " << what << "; viewing what is there\n";
  return true;
}

// Runs drawn side by side at most: each has a 3D view of its own.
constexpr size_t kMostRuns = 6;

// The runs a positional argument names: a run's folder, or a study's (its
// settings' runs, settings/NNN, in order).
std::vector<fs::path> runsNamed(const fs::path& path) {
  // A study's own folders only: a link among them is not followed.
  std::error_code ec;
  if (!fs::is_regular_file(path / "study.csv", ec) || !fs::is_directory(fs::symlink_status(path / "settings", ec)))
    return {path};
  std::vector<fs::path> runs;
  for (const auto& entry : fs::directory_iterator(path / "settings", ec))
    if (entry.is_directory() && !entry.is_symlink()) runs.push_back(entry.path());
  std::sort(runs.begin(), runs.end());
  return runs;
}

}  // namespace

int viewCommand(const Arguments& arguments) {
  if (arguments.positional.empty()) {
    std::cerr << "usage: trephine view RUN_DIR [--triangles N] [--partial]\n"
                 "       trephine view RUN_DIR RUN_DIR... --out DIR   (side by side; a study's folder: its settings)\n";
    return kUsage;
  }
  std::vector<fs::path> runs;
  std::error_code ec;
  for (const std::string& argument : arguments.positional) {
    if (!fs::is_directory(argument, ec)) {
      std::cerr << "trephine view: " << argument << ": not a directory (the output directory of trephine run, or "
                   "of trephine study)\n";
      return kSceneError;
    }
    for (const fs::path& run : runsNamed(argument)) runs.push_back(run);
  }
  if (runs.empty()) {
    std::cerr << "trephine view: " << arguments.positional[0] << ": a study with no settings' runs\n";
    return kSceneError;
  }
  if (runs.size() > kMostRuns) {
    std::cerr << "trephine view: " << runs.size() << " runs are more than " << kMostRuns
              << " side by side: name the runs to compare (a study's are in its settings/ folder)\n";
    return kUsage;
  }
  const bool single = runs.size() == 1;
  const bool study = arguments.positional.size() == 1 && !single;
  if (!single && !study && !arguments.get("--out")) {
    std::cerr << "trephine view: runs side by side need --out DIR (the folder of their viewer)\n";
    return kUsage;
  }
  for (const fs::path& run : runs)
    if (!runOutputsUsable(run, arguments.has("--partial"))) return kSceneError;
  // The viewer plugin provides the browser viewer and writes the run's data for it.
  PluginLoader loader;
  Registry registry;
  if (const auto error = loader.load("viewer", registry)) {
    std::cerr << "trephine view: " << *error << "\n";
    return kRuntimeFailure;
  }
  const RunViewer* viewer = registry.service<RunViewer>();
  if (!viewer) {
    std::cerr << "trephine view: the viewer plugin provides no RunViewer\n";
    return kRuntimeFailure;
  }
  const fs::path assets = viewer->assets();
  if (assets.empty()) {
    std::cerr << "trephine view: the browser viewer was not built: it needs Node.js and npm (tools/setup installs "
                 "them and the viewer's packages, then builds it). ParaView opens the run's .pvd files meanwhile.\n";
    return kRuntimeFailure;
  }
  const auto out = arguments.get("--out");
  const fs::path view = out ? fs::path(*out) : single ? runs[0] / "view" : fs::path(arguments.positional[0]) / "view";
  // The viewer's folder is emptied of its data: never a run's own folder.
  for (const fs::path& run : runs)
    if (fs::exists(view, ec) && fs::equivalent(view, run, ec)) {
      std::cerr << "trephine view: --out " << view.string() << " is the run " << run.string()
                << " itself: give the viewer a folder of its own\n";
      return kUsage;
    }
  try {
    size_t triangles = 8000;
    if (auto value = arguments.get("--triangles")) {
      char* end = nullptr;
      const long long n = std::strtoll(value->c_str(), &end, 10);
      if (end == value->c_str() || *end || n < 1000) {
        std::cerr << "trephine view: --triangles takes a whole number of 1000 or more, not '" << *value << "'\n";
        return kUsage;
      }
      triangles = size_t(n);
    }
    // The viewer's folder as --out names it, or the run's (or study's) own
    // `view`, reached without following a link: a `view` planted as a link
    // to another folder is refused, never emptied or written into.
    const OutputFolder viewFolder = out ? OutputFolder::create(view)
                                        : OutputFolder::open(view.parent_path()).subfolder(view.filename());
    std::string manifests;  // side by side: every run's, in data/manifest.js
    viewFolder.remove("data");
    const OutputFolder data = viewFolder.subfolder("data");
    for (size_t k = 0; k < runs.size(); ++k) {
      const std::string folder = single ? "" : "run_" + std::to_string(k) + "/";
      const ViewerDataSummary summary = viewer->writeViewerData(runs[k], data, folder, k, triangles);
      for (const std::string& warning : summary.warnings)
        std::cerr << "trephine view: warning: " << (runs[k] / warning).string() << "\n";
      if (summary.rowsLeftOut > summary.warnings.size())
        std::cerr << "trephine view: warning: " << summary.rowsLeftOut << " rows of " << (runs[k] / "trace.csv").string()
                  << " in all were left out of the plots\n";
      if (!single) {
        manifests += readRegularFile(view / "data" / folder / "manifest.js", size_t(1) << 30);
        std::cout << "run " << k << "     " << runs[k].string() << "\n";
      }
      std::cout << "          " << summary.frames << " frames over " << summary.end << " s, " << summary.parts
                << " parts, " << summary.files << " files (" << summary.bytes / 1e6 << " MB) in " << summary.chunks
                << " chunks" << (summary.plots ? ", plots from trace.csv" : ", no plots (no trace.csv)") << "\n";
      if (summary.surfaceTriangles)
        std::cout << "          skull: " << summary.surfaceTriangles << " triangles drawn as " << summary.drawnTriangles
                  << " while playing or turning (untouched bone "
                  << (summary.pooledFactor ? "from its volume pooled over " + std::to_string(summary.pooledFactor) +
                                                 "^3 voxels, on its surface"
                                           : "clustered at " + std::to_string(summary.coarseCell) + " mm")
                  << ", drilled blocks "
                  << (summary.drilledCell > 0 ? "at " + std::to_string(summary.drilledCell) + " mm" : "whole")
                  << "; --triangles sets it), " << summary.stillTriangles << " when still\n";
    }
    if (!single) writeFileAtomically(data, "manifest.js", [&](std::ostream& out) { out << manifests; });
    // Copied as new files renamed into place: a link at index.html or
    // viewer.js is replaced, never written through. The licences of what
    // the bundle holds go too, when the build wrote them.
    for (const char* file : {"index.html", "viewer.js", "viewer.js.LICENSES.txt"}) {
      if (!fs::is_regular_file(assets / file, ec) && std::string(file) == "viewer.js.LICENSES.txt") continue;
      const std::string bytes = readRegularFile(assets / file, size_t(1) << 30);
      writeFileAtomically(viewFolder, file, [&](std::ostream& out) { out << bytes; });
    }
    std::cout << "viewer    " << (view / "index.html").string() << " (open it in a browser"
              << (single ? "" : "; the runs side by side on one clock") << ")\n";
  } catch (const ViewerDataError& e) {
    std::cerr << "trephine view: " << e.what() << "\n";
    return kSceneError;
  } catch (const FolderInputError& e) {
    std::cerr << "trephine view: " << e.what() << "\n";
    return kSceneError;
  } catch (const FileWriteError& e) {
    std::cerr << "trephine view: " << e.what() << "\n";
    return kRuntimeFailure;
  } catch (const fs::filesystem_error& e) {
    std::cerr << "trephine view: " << e.what() << "\n";
    return kRuntimeFailure;
  }
  return kOk;
}

}  // namespace trephine::cli
