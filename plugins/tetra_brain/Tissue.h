#pragma once
// One tissue of a brain: the tetrahedra of one label of a TetraBrain's mesh,
// named (the component's name is the tissue's in the metrics), with what
// resecting it takes and costs:
//  - removalEnergy (J/mm^3): the work a resecting tool (an aspirator) spends
//    per volume removed, its resistance to removal;
//  - vascularity (ml of blood per ml of tissue): the blood lost when it is
//    removed uncoagulated (cerebral blood volume: grey matter about 0.05,
//    white matter about 0.025, a high-grade glioma two to three times grey
//    matter's, a vessel 1);
//  - critical: a vessel or eloquent cortex, never removed; a tool touching it
//    is an event.
// Its material for the FEM stays the FEM's (LabelMaterial for another one).
// Declared with the brain at init: a label the mesh does not hold is an
// error at `label`; a Resection after the tissues warns of labels none declares.
#include "framework/core/Component.h"
#include "plugins/tetra_brain/TetraBrain.h"

namespace trephine::tetra {

class Tissue final : public Component {
 public:
  static constexpr std::string_view kTypeName = "Tissue";

  void init(InitContext& context) override;

 private:
  Link<TetraBrain> l_mesh{this, "mesh", {.help = "The brain this tissue is part of", .required = true, .initOnly = true}};
  Field<int> d_label{this, "label", 1, {.help = "The label of its tetrahedra in the mesh", .required = true}};
  // Calibrated, not measured: 0.05 J/mm^3 removes 20 mm^3 a second for each
  // watt an aspirator puts into the tissue; cortical bone's cutting energy
  // (VoxelSkull) is 0.2 J/mm^3.
  Field<double> d_removalEnergy{this,
                                "removalEnergy",
                                0.05,
                                {.help = "Work a resecting tool spends per volume of this tissue removed (its "
                                         "resistance to removal: a fibrous tumour more than white matter)",
                                 .unit = "J/mm^3",
                                 .min = 0.0,
                                 .minExclusive = true}};
  Field<double> d_vascularity{this,
                              "vascularity",
                              0.03,
                              {.help = "Blood volume per tissue volume, lost when the tissue is removed "
                                       "uncoagulated: grey matter about 0.05, white matter 0.025, a high-grade "
                                       "glioma 0.1 to 0.15, a vessel 1",
                               .unit = "ml/ml",
                               .min = 0.0}};
  Field<bool> d_critical{this,
                         "critical",
                         false,
                         {.help = "A vessel or eloquent cortex: never removed, and a tool touching it is an event"}};
};

}  // namespace trephine::tetra
