#include "plugins/fem/LabelMaterial.h"

#include "framework/core/Lifecycle.h"
#include "plugins/fem/MaterialPlausibility.h"

namespace trephine::fem {

void LabelMaterial::init(InitContext& context) {
  TLEDForceField& fem = *l_fem;
  if (!fem.hasModel()) return;  // the FEM's own error is reported
  if (d_density.isSet())
    if (auto why = implausibleDensity(d_density.value())) context.warning(d_density, *why);
  if (d_youngModulus.isSet())
    if (auto why = implausibleYoungModulus(d_youngModulus.value())) context.warning(d_youngModulus, *why);
  ElementMaterial material = fem.material();
  if (d_density.isSet()) material.density = d_density.value();
  if (d_youngModulus.isSet()) material.youngModulus = d_youngModulus.value();
  if (d_poissonRatio.isSet()) material.poissonRatio = d_poissonRatio.value();
  if (auto error = fem.assignLabelMaterial(d_label.value(), material)) context.error(d_label, *error);
}

}  // namespace trephine::fem
