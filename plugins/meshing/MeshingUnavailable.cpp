// The meshing functions of a build without CGAL Mesh_3
// (-DTREPHINE_WITH_MESHING=OFF): each says what is missing.
#include "plugins/meshing/ImplicitMesher.h"
#include "plugins/meshing/LabelledImageMesher.h"
#include "plugins/meshing/Meshing.h"

namespace trephine::tetra {

bool meshingBuilt() { return false; }

TetMesh meshImplicitSolid(const ImplicitSolid&, int) {
  throw MeshingUnavailable(meshingMissingMessage("meshing a solid into tetrahedra"));
}
TetMesh meshImplicitSolidAtSize(const ImplicitSolid&, double) {
  throw MeshingUnavailable(meshingMissingMessage("meshing a solid into tetrahedra"));
}
TetMesh meshLabelledImage(const LabelledImage&, int) {
  throw MeshingUnavailable(meshingMissingMessage("meshing a labelled image into tetrahedra"));
}
TetMesh meshLabelledImageAtSize(const LabelledImage&, double) {
  throw MeshingUnavailable(meshingMissingMessage("meshing a labelled image into tetrahedra"));
}

}  // namespace trephine::tetra
