#pragma once
// Another material for the elements of one tissue label of a TLEDForceField's
// mesh (the atlas brain's grey matter 5 and white matter 6, say); the others
// keep the FEM's own. Any field left unset takes the FEM's value.
#include "framework/core/Component.h"
#include "plugins/fem/TLEDForceField.h"

namespace trephine::fem {

class LabelMaterial final : public Component {
 public:
  static constexpr std::string_view kTypeName = "LabelMaterial";

  void init(InitContext& context) override;

 private:
  Link<TLEDForceField> l_fem{this, "fem", {.help = "The FEM whose elements this sets", .required = true}};
  Field<int> d_label{this, "label", 0, {.help = "The tissue label of the elements", .required = true}};
  Field<double> d_density{
      this, "density", 1e-6, {.help = "Mass density", .unit = "kg/mm^3", .min = 0.0, .minExclusive = true}};
  Field<double> d_youngModulus{
      this, "youngModulus", 30.0, {.help = "Young's modulus", .unit = "kPa", .min = 0.0, .minExclusive = true}};
  Field<double> d_poissonRatio{this, "poissonRatio", 0.3, {.help = "Poisson's ratio", .min = -0.99, .max = 0.499}};
};

}  // namespace trephine::fem
