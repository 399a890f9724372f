#pragma once
// Whether this build holds the meshing plugin (CGAL Mesh_3, whose open-source
// licence is GPL-3.0-or-later). A build configured with
// -DTREPHINE_WITH_MESHING=OFF is wholly under the project's own licence; its
// meshing functions throw MeshingUnavailable, saying what is missing.
#include <stdexcept>
#include <string>

namespace trephine::tetra {

struct MeshingUnavailable : std::runtime_error {
  explicit MeshingUnavailable(const std::string& what);
};

// True when the meshing functions (ImplicitMesher.h, LabelledImageMesher.h,
// makeBrainPhantom) mesh; false when they throw MeshingUnavailable.
bool meshingBuilt();

// What a build without meshing lacks, and how to get it.
std::string meshingMissingMessage(const std::string& feature);

}  // namespace trephine::tetra
