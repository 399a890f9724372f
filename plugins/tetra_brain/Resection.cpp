#include "plugins/tetra_brain/Resection.h"

#include <cmath>
#include <iomanip>

#include "framework/core/AtomicFile.h"
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
  if (auto error = l_mesh->enableResection(context.events())) context.error(l_mesh, *error);
  if (!d_file.value().empty()) {
    if (auto bad = FinishContext::checkFileName(d_file.value())) context.error(d_file, *bad);
  }
}

void Resection::declareOutputs(std::vector<OutputFile>& outputs) const {
  if (!d_file.value().empty()) outputs.push_back({d_file.value(), &d_file});
}

void Resection::finish(FinishContext& context) {
  const BrainResection* resection = l_mesh->resection();
  if (!resection || d_file.value().empty() || context.outputDirectory().empty()) return;
  if (!context.claimOutput(*this, d_file.value())) return;
  const std::filesystem::path path = context.outputDirectory() / d_file.value();
  const size_t columns = resection->recordColumns();
  const std::span<const double> rows = resection->recordRows();
  try {
    writeFileAtomically(path, [&](std::ostream& out) {
      out << "t,removed_mm3,blood_loss_ml,critical_contact_s";
      for (const TissueSpec& tissue : l_mesh->tissues().tissues()) out << ",removed_mm3." << tissue.name;
      out << '\n' << std::setprecision(9);
      for (size_t r = 0; r + columns <= rows.size(); r += columns) {
        for (size_t c = 0; c < columns; ++c) out << (c ? "," : "") << rows[r + c];
        out << '\n';
      }
    });
  } catch (const std::exception& e) {
    context.error(*this, e.what());
  }
}

std::optional<SummaryBlock> Resection::summaryBlock() const {
  const BrainResection* resection = l_mesh->resection();
  if (!resection) return std::nullopt;
  SummaryBlock block;
  block.name = "resection";
  const ResectionTotals& totals = resection->totals();
  const auto& tissues = l_mesh->tissues().tissues();
  for (size_t i = 0; i < tissues.size(); ++i) {
    block.figures.push_back({"removed_mm3." + tissues[i].name, totals.removed_mm3[i]});
  }
  for (size_t i = 0; i < tissues.size(); ++i)
    block.figures.push_back({"remaining_mm3." + tissues[i].name, totals.volume_mm3[i] - totals.removed_mm3[i]});
  for (size_t i = 0; i < tissues.size(); ++i)
    block.figures.push_back({"coagulated_mm3." + tissues[i].name, totals.coagulated_mm3[i]});
  block.figures.push_back({"blood_loss_ml", totals.bloodLoss_ml});
  block.figures.push_back({"critical_contact_s", totals.criticalContact_s});
  block.figures.push_back({"critical_contacts", double(totals.criticalContacts)});
  block.figures.push_back({"removed_tetrahedra", double(totals.removedTets)});
  block.figures.push_back({"remaining_tetrahedra", double(resection->remaining().aliveCount())});
  block.figures.push_back({"energy_in_J", totals.energyIn_J});
  block.toolsOn = static_cast<const ShellContactTarget*>(&*l_mesh);
  return block;
}

void Resection::reportCounters(std::vector<Counter>& counters) const {
  for (const auto& [name, mm3] : m_volumes) counters.push_back({"volume_mm3." + name, mm3});
}

}  // namespace trephine::tetra
