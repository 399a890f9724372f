#pragma once
// Resection of a brain's tissues: the owner of what removing tissue from one
// TetraBrain does and measures. Placed after the brain's Tissue components
// (it reads the tissues they declared) and before the tools that resect it:
// a brain with no tissue declared is an error here, and labels of the mesh
// that no tissue declares are warned of by number (their tetrahedra stay
// brain, deform and are touched, but no tool removes them). From its init
// the brain's tools with a tissue action (an aspirator, a bipolar forceps)
// remove and coagulate tissue (TissueRemoval.h says how). It writes the
// `resection` block of summary.json (removed and remaining volume by tissue,
// blood loss, time on critical tissue, and per tool its path length and
// forces) and `file` (resection.csv by default): the totals over time, a row
// a millisecond.
#include <map>
#include <string>
#include <vector>

#include "framework/core/Component.h"
#include "plugins/tetra_brain/TetraBrain.h"

namespace trephine::tetra {

class Resection final : public Component {
 public:
  static constexpr std::string_view kTypeName = "Resection";

  void init(InitContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;
  void declareOutputs(std::vector<OutputFile>& outputs) const override;
  void finish(FinishContext& context) override;
  std::optional<SummaryBlock> summaryBlock() const override;

 private:
  Link<TetraBrain> l_mesh{
      this, "mesh", {.help = "The brain whose tissues are resected (place this after its Tissue components)",
                     .required = true, .initOnly = true}};
  Field<std::string> d_file{this,
                            "file",
                            "resection.csv",
                            {.help = "The totals over time, in the run directory: t (s), removed_mm3, blood_loss_ml, "
                                     "critical_contact_s, then removed_mm3 of each tissue (a row a millisecond); "
                                     "empty writes none"}};

  // Per tissue (declaration order): its name and volume at rest (mm^3).
  std::vector<std::pair<std::string, double>> m_volumes;
};

}  // namespace trephine::tetra
