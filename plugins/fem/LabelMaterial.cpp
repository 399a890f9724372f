#include "plugins/fem/LabelMaterial.h"

#include "framework/core/Lifecycle.h"

namespace trephine::fem {

void LabelMaterial::init(InitContext& context) {
  TLEDForceField& fem = *l_fem;
  if (!fem.hasModel()) return;  // the FEM's own error is reported
  ElementMaterial material = fem.material();
  if (d_density.isSet()) material.density = d_density.value();
  if (d_youngModulus.isSet()) material.youngModulus = d_youngModulus.value();
  if (d_poissonRatio.isSet()) material.poissonRatio = d_poissonRatio.value();
  if (auto error = fem.assignLabelMaterial(d_label.value(), material)) context.error(d_label, *error);
}

}  // namespace trephine::fem
