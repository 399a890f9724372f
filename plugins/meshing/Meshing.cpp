#include "plugins/meshing/Meshing.h"

namespace trephine::tetra {

MeshingUnavailable::MeshingUnavailable(const std::string& what) : std::runtime_error(what) {}

std::string meshingMissingMessage(const std::string& feature) {
  return feature +
         " needs the meshing plugin (CGAL Mesh_3, GPL-3.0-or-later), which this build leaves out; the brain and "
         "sphere phantoms, `trephine mesh` and labelled-image meshing come with it (configure with "
         "-DTREPHINE_WITH_MESHING=ON and libcgal-dev installed), or load a tetrahedral mesh file instead";
}

}  // namespace trephine::tetra
