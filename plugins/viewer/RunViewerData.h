#pragma once
// The data of a run's browser viewer, read from the .pvd indexes a
// VtkExporter wrote (and from trace.csv for the plots), written as
//   data/FOLDER/manifest.js  trephineRuns[K] = {name, source, folder, end, parts, frames, files,
//                     plots, summary} (plugins/viewer/web/src/runData.js describes it)
//   data/FOLDER/chunk_N.js   trephineChunk(K, N, {"vtk/brain_00003.vtu": "<base64>", ...})
// A part is what one exporter file series shows (brain_, tool_, skull_); its
// states are its files in time, a .vtm's as the blocks that changed. Files
// go into chunks of about `chunkBytes` in the order the frames first need
// them, so the first frame loads first and in parallel.
//
// A skull of a million triangles is more than a browser without a graphics
// card draws 30 times a second (SwiftShader here draws every frame of a run's
// 30 a second with an 8,000-triangle skull, 27 with 15,000), so its blocks are
// simplified (VertexClustering) to at
// most `blockTriangles`: the blocks the drill changed are kept whole while
// they fit in half of that (else clustered, finer than the rest), and the
// blocks it never touched are clustered into the remainder. A second level,
// ten times finer, is drawn while the view stands still (neither playing
// nor turning), loaded after everything playback needs. Those surfaces go
// into the chunks as binary meshes (.tri: "TRI1", uint32 point and triangle
// counts, float32 points in mm, uint32 corners).
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "framework/core/OutputFolder.h"
#include "framework/runtime/RunViewer.h"

namespace trephine::viewer {

// The viewer's RunViewer service (ViewerPlugin.cpp registers it).
std::shared_ptr<RunViewer> makeRunViewer();

// Writes `dataDirectory` / `folder` (emptied first) from `runDirectory`, as
// run `index` of the viewer (RunViewer::writeViewerData).
ViewerDataSummary writeViewerData(const std::filesystem::path& runDirectory,
                                  const OutputFolder& dataDirectory, const std::string& folder = "",
                                  size_t index = 0, size_t blockTriangles = 8000, uint64_t chunkBytes = 4u << 20);


}  // namespace trephine::viewer
