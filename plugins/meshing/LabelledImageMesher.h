#pragma once
// Tetrahedral meshing of a labelled image (a segmentation: each voxel holds
// the integer label of its tissue, 0 outside) with CGAL Mesh_3's labelled
// image domain: one mesh whose tetrahedra keep the label of the region they
// fill, with conforming interfaces between regions. The tetrahedron count
// is aimed at as in ImplicitMesher.h (the size re-run from the achieved
// count, at most four runs), then slivers are removed.
#include <array>
#include <cstdint>
#include <vector>

#include "framework/math/Math.h"
#include "framework/data/TetMesh.h"

namespace trephine::tetra {

struct LabelledImage {
  std::array<int32_t, 3> dims{0, 0, 0};  // voxels along x, y, z
  Vec3 spacing = Vec3::Ones();           // mm
  Vec3 origin = Vec3::Zero();            // mm, centre of voxel (0, 0, 0)
  std::vector<int32_t> labels;           // x fastest; 0 is outside, others >= 1
};

// Meshes the labelled voxels at about `targetTets` tetrahedra. Throws
// std::invalid_argument when targetTets is outside [100, 2000000], when the
// image has no labelled voxel, or a label is negative.
TetMesh meshLabelledImage(const LabelledImage& image, int targetTets);
// One refinement with cells and surface facets of circumradius at most
// `size` (mm), then the slivers' removal.
TetMesh meshLabelledImageAtSize(const LabelledImage& image, double size);

}  // namespace trephine::tetra
