#pragma once
// What the mesh back-ends (embree, bullet) count of their copy of a target's
// surface, reported the same way by both.
#include <cstdint>
#include <vector>

#include "framework/core/Component.h"

namespace trephine {

struct MeshSurfaceCounters {
  double buildMs = 0;          // ms, extracting the surface and building the library's structure at bind
  uint64_t rebuiltBlocks = 0;  // blocks re-extracted and rebuilt after cuts, or rebuilt after deformation
  uint64_t failedBlocks = 0;   // blocks the library could not take (counted in the haptic loop, not thrown)
  uint64_t contactFrames = 0;  // collide() calls that found contact
  // Where a changed surface's time goes (ms, summed over the run): the
  // target's re-extraction of its changed blocks (the adapter's), the
  // library's rebuild of those blocks, and its update of the structure over
  // all blocks (Embree's top-level scene; Bullet's broadphase).
  double extractMs = 0, blockBuildMs = 0, topBuildMs = 0;

  void report(std::vector<Counter>& counters, size_t triangles) const {
    counters.push_back({"contact_frames", double(contactFrames)});
    counters.push_back({"triangles", double(triangles)});
    counters.push_back({"surface_build_ms", buildMs});
    counters.push_back({"rebuilt_blocks", double(rebuiltBlocks)});
    if (failedBlocks) counters.push_back({"failed_blocks", double(failedBlocks)});
    if (rebuiltBlocks) {
      counters.push_back({"block_extract_ms", extractMs});
      counters.push_back({"block_build_ms", blockBuildMs});
      counters.push_back({"top_build_ms", topBuildMs});
    }
  }
};

}  // namespace trephine
