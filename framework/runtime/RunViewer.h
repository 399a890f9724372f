#pragma once
// What `trephine view` asks of the viewer plugin, which provides it as a
// registry service: where the built browser viewer is, and a run's data
// written for it (plugins/viewer/RunViewerData.h says what the data are).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "framework/core/Interface.h"
#include "framework/core/OutputFolder.h"

namespace trephine {

// Bad or missing run data; the message names the file and what was expected.
class ViewerDataError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ViewerDataSummary {
  size_t frames = 0, parts = 0, files = 0, chunks = 0;
  // Of block parts (a skull): in the files, in the viewer while moving, still.
  size_t surfaceTriangles = 0, drawnTriangles = 0, stillTriangles = 0;
  double coarseCell = 0, drilledCell = 0;  // mm of their clustering (0: none)
  int pooledFactor = 0;  // the untouched bone: the volume pooled over this many voxels a side (0: clustered)
  uint64_t bytes = 0;                      // of the VTK files packed
  double end = 0;                          // s
  bool plots = false;
  // What the viewer left out, by file and line ("trace.csv:12: ..."), the
  // first few; and how many rows of the trace were left out in all.
  std::vector<std::string> warnings;
  size_t rowsLeftOut = 0;
};

class TREPHINE_INTERFACE RunViewer {
 public:
  static constexpr std::string_view kTypeName = "RunViewer";
  virtual ~RunViewer();
  // The folder of the built browser viewer (index.html, viewer.js), or empty.
  virtual std::filesystem::path assets() const = 0;
  // Writes run `index` of the viewer's data into `dataDirectory` / `folder`
  // (emptied first; `folder` "" for a viewer of one run, "run_K/" for the
  // K-th of runs compared side by side, whose manifests the caller joins),
  // surfaces of block parts simplified to at most `blockTriangles`. Throws
  // ViewerDataError.
  virtual ViewerDataSummary writeViewerData(const std::filesystem::path& runDirectory,
                                            const OutputFolder& dataDirectory, const std::string& folder,
                                            size_t index, size_t blockTriangles) const = 0;
};

}  // namespace trephine
