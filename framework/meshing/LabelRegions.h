#pragma once
// The connected regions of a labelled image (each label's voxels joined
// across faces). A segmentation from an atlas or a scanner's software
// (FreeSurfer's aseg) holds many regions of a few voxels: the mesher meshes
// each on its own with a few dozen tetrahedra, whatever the cell size, so a
// requested count cannot be met below that floor. Counted here, and merged
// into their surroundings when asked.
#include <cstddef>

#include "framework/meshing/TetMeshing.h"

namespace trephine {

struct LabelRegionCount {
  size_t regions = 0;      // labelled regions (label 0 is outside, not counted)
  size_t small = 0;        // of fewer than the given voxels
  size_t smallVoxels = 0;  // voxels in those
};

LabelRegionCount countLabelRegions(const LabelledImage& image, size_t smallVoxels);

// Gives each region of fewer than `minVoxels` voxels the label most of the
// voxels across its faces have (0 where that is outside; the image's border
// counts as outside); returns what it merged.
LabelRegionCount mergeSmallLabelRegions(LabelledImage& image, size_t minVoxels);

}  // namespace trephine
