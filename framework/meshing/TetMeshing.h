#pragma once
// Tetrahedral meshing of a solid given by an implicit function (negative
// inside) or of a labelled image (a segmentation), at a requested
// tetrahedron count or cell size. The mesher is the `meshing` plugin's (CGAL
// Mesh_3, GPL-3.0-or-later), loaded from the plugin search path the first
// time a mesh is asked for: nothing else of the project links CGAL, so a
// build or an installation without that plugin is wholly under the project's
// own licence and says, when a mesh is asked for, what is missing.
//
// What the mesher guarantees (plugins/meshing/CgalMesher.cpp): Delaunay
// refinement with a cell size guessed from the count and re-run with the
// size rescaled from the achieved count (at most four runs); the run closest
// to the target has its slivers removed (perturbation and exudation:
// smallest dihedral angle 10 deg). From 1500 tets up the count is within 2%
// of the target on the brain phantom. Deterministic: the same input gives
// identical nodes and tetrahedra on every call of the same build. Every
// tetrahedron has positive signedVolume(), every node belongs to a
// tetrahedron; an implicit solid's labels are all 1 (or its regions'), a
// labelled image's tetrahedra keep the label of the region they fill.
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <numbers>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "framework/data/TetMesh.h"
#include "framework/math/Math.h"

namespace trephine {

struct ImplicitSolid {
  std::function<double(const Vec3&)> distance;  // negative inside, zero on the surface, about unit gradient there (mm)
  Vec3 centre = Vec3::Zero();                   // of a sphere holding the solid
  double boundingRadius = 1;                    // mm
  // The refined count of Mesh_3 at cell size s is about volumeTerm / s^3 +
  // surfaceTerm / s^2: the first guess of the size (about 4.2 times the
  // volume and 4.3 times the area for a smooth solid).
  double volumeTerm = 1, surfaceTerm = 0;
  double leastFacetDistance = 0;  // mm: surface facets lie within max(this, size / 10) of the surface
  // Optional: the solid's regions (a tumour in the brain), the label (1 and
  // up) of a point inside; the mesh's surfaces between regions then conform
  // to them and each tetrahedron keeps its region's label. Without it every
  // label is 1.
  std::function<int32_t(const Vec3&)> region;
  // Optional: finer cells and facets at a point (a factor in (0, 1] of the
  // size the count asks for): a small region resolved finer than the rest.
  std::function<double(const Vec3&)> sizeFactor;
};

// A ball of `radius` (mm) at the origin.
inline ImplicitSolid ballSolid(double radius) {
  return {[radius](const Vec3& p) { return p.norm() - radius; },
          Vec3::Zero(),
          1.2 * radius,
          4.2 * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius,
          4.3 * 4.0 * std::numbers::pi * radius * radius,
          0.0,
          {},
          {}};
}

struct LabelledImage {
  std::array<int32_t, 3> dims{0, 0, 0};  // voxels along x, y, z
  Vec3 spacing = Vec3::Ones();           // mm
  Vec3 origin = Vec3::Zero();            // mm, centre of voxel (0, 0, 0)
  std::vector<int32_t> labels;           // x fastest; 0 is outside, others >= 1
};

// What the meshing plugin provides. Throws std::invalid_argument for a
// count outside [100, 2000000], a size that is not positive, an image with
// no labelled voxel or a negative label.
class TetMesher {
 public:
  static constexpr std::string_view kTypeName = "TetMesher";
  virtual ~TetMesher();
  virtual TetMesh meshImplicitSolid(const ImplicitSolid& solid, int targetTets) const = 0;
  // One refinement with cells and surface facets of circumradius at most `size` (mm).
  virtual TetMesh meshImplicitSolidAtSize(const ImplicitSolid& solid, double size) const = 0;
  virtual TetMesh meshLabelledImage(const LabelledImage& image, int targetTets) const = 0;
  virtual TetMesh meshLabelledImageAtSize(const LabelledImage& image, double size) const = 0;
};

// No meshing plugin on the search path (or it failed to load): the message
// says what was asked for, what is missing and how to get it.
struct MeshingUnavailable : std::runtime_error {
  explicit MeshingUnavailable(const std::string& what);
};

// The meshing plugin's mesher, loaded on first use from the plugin search
// path (TREPHINE_PLUGIN_PATH, the build's and the installation's plugin
// folders). Throws MeshingUnavailable naming `feature`.
const TetMesher& tetMesher(std::string_view feature = "tetrahedral meshing");
// The same from the folders given, loaded anew (tests of a missing plugin).
const TetMesher& tetMesherFrom(const std::vector<std::filesystem::path>& searchPath, std::string_view feature);
// Whether tetMesher() finds a mesher.
bool meshingAvailable();

// tetMesher()'s, for the callers that mesh once.
TetMesh meshImplicitSolid(const ImplicitSolid& solid, int targetTets);
TetMesh meshImplicitSolidAtSize(const ImplicitSolid& solid, double size);
TetMesh meshLabelledImage(const LabelledImage& image, int targetTets);
TetMesh meshLabelledImageAtSize(const LabelledImage& image, double size);

}  // namespace trephine
