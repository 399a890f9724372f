// The brain's mechanics: TLED neo-Hookean FEM on the CPU, its constraints,
// body forces and per-tissue materials.
#include "framework/core/Registry.h"
#include "plugins/fem/FixedConstraint.h"
#include "plugins/fem/Gravity.h"
#include "plugins/fem/LabelMaterial.h"
#include "plugins/fem/TLEDForceField.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.add<trephine::fem::TLEDForceField>(
      "TLEDForceField", "Deforms a TetraBrain: TLED, compressible neo-Hookean, explicit central differences");
  registrar.add<trephine::fem::FixedConstraint>("FixedConstraint",
                                                "Holds FEM nodes at rest: by index, in a box, or of a tissue label");
  registrar.add<trephine::fem::Gravity>("Gravity", "Uniform body acceleration on every node of a FEM");
  registrar.add<trephine::fem::LabelMaterial>("LabelMaterial", "Own material for the elements of one tissue label");
}
