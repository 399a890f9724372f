#include "plugins/tetra_brain/Resection.h"

#include <cmath>

#include "framework/core/Lifecycle.h"

namespace trephine::tetra {

void Resection::init(InitContext& context) {
  const TetraBrain& brain = *l_mesh;
  const TetMesh& mesh = brain.mesh();
  if (mesh.tetCount() == 0) return;  // the brain's own error says why
  const TissueTable& tissues = brain.tissues();
  if (tissues.empty()) {
    context.error(l_mesh, "no tissue of " + brain.path() +
                              " is declared before this component: add a Tissue (mesh=\"@" + brain.name() +
                              "\", label=...) for each tissue to resect, and place them before it");
    return;
  }
  const std::map<int32_t, size_t> undeclared = tissues.undeclared(mesh.labels);
  if (!undeclared.empty()) {
    std::string labels;
    for (const auto& [label, count] : undeclared)
      labels += (labels.empty() ? "" : ", ") + std::to_string(label) + " (" + std::to_string(count) + ")";
    context.warning(l_mesh, "the mesh's labels " + labels +
                                " (tetrahedra) are no declared tissue: they deform and are touched but no tool "
                                "removes them; declare a Tissue for each (before this component: one after it is "
                                "not seen here), critical if it must never be removed");
  }
  std::map<int32_t, double> volume;
  for (size_t t = 0; t < mesh.tetCount(); ++t) {
    const auto& tet = mesh.tets[t];
    volume[mesh.labels.empty() ? 0 : mesh.labels[t]] +=
        std::abs(signedVolume(mesh.nodes[tet[0]], mesh.nodes[tet[1]], mesh.nodes[tet[2]], mesh.nodes[tet[3]]));
  }
  for (const TissueSpec& tissue : tissues.tissues()) m_volumes.emplace_back(tissue.name, volume[tissue.label]);
}

void Resection::reportCounters(std::vector<Counter>& counters) const {
  for (const auto& [name, mm3] : m_volumes) counters.push_back({"volume_mm3." + name, mm3});
}

}  // namespace trephine::tetra
