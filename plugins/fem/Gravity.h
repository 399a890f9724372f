#pragma once
// A uniform body acceleration on every node of a TLEDForceField's mesh. A
// scene without this component has no gravity.
#include "framework/core/Component.h"
#include "plugins/fem/TLEDForceField.h"

namespace trephine::fem {

class Gravity final : public Component {
 public:
  static constexpr std::string_view kTypeName = "Gravity";

  void init(InitContext& context) override;

 private:
  Link<TLEDForceField> l_fem{this, "fem", {.help = "The FEM whose nodes this accelerates", .required = true}};
  Field<Vec3> d_acceleration{
      this, "acceleration", Vec3(0, 0, -9810), {.help = "Acceleration (Table 6.1: 9810 mm/s^2)", .unit = "mm/s^2"}};
};

}  // namespace trephine::fem
