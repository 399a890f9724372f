#include "plugins/tetra_brain/Tissue.h"

#include <cstdio>

#include "framework/core/Lifecycle.h"
#include "framework/core/Strings.h"

namespace trephine::tetra {

namespace {
// J/mm^3: harder to remove than this is harder than cortical bone is to cut
// (0.2 J/mm^3): a units slip (J/cm^3 or J/m^3 are a thousand and a billion
// times smaller numbers for the same tissue, but J/ml is J/cm^3).
constexpr double kHarderThanBone = 0.2;
}  // namespace

void Tissue::init(InitContext& context) {
  if (d_vascularity.value() > 1.0) {
    const std::string percent = formatDouble(d_vascularity.value() / 100.0);
    context.error(d_vascularity, "is a fraction, ml of blood per ml of tissue (0 to 1), not a percentage: " +
                                     formatDouble(d_vascularity.value()) + " is " +
                                     formatDouble(100 * d_vascularity.value()) + "%; " + percent +
                                     " if a percentage was meant");
  }
  if (d_removalEnergy.value() > kHarderThanBone)
    context.warning(d_removalEnergy, formatDouble(d_removalEnergy.value()) +
                                         " J/mm^3 is harder to remove than cortical bone is to cut (0.2 J/mm^3): a "
                                         "tissue of the brain is softer by far; was J/cm^3 (J/ml) meant? That is a "
                                         "thousandth of the number in J/mm^3");
  if (d_critical.value() && d_removalEnergy.isSet())
    context.note(d_removalEnergy, "a critical tissue is never removed: removalEnergy is not used");
  TetraBrain& brain = *l_mesh;
  TissueSpec spec;
  spec.name = name();
  spec.label = d_label.value();
  spec.removalEnergy = d_removalEnergy.value();
  spec.vascularity = d_vascularity.value();
  spec.critical = d_critical.value();
  if (auto error = brain.declareTissue(spec)) context.error(d_label, *error);
}

}  // namespace trephine::tetra
