#pragma once
// A tumour placed in a brain mesh that has none (an atlas, a patient's
// brain without a lesion): the tetrahedra whose centre lies in a ball take a
// label of their own, which a Tissue then names. Placed after the brain and
// before its tissues and its deformation (they read the labels at load).
// The ball's surface is not meshed: the tumour's boundary follows the
// tetrahedra, as jagged as they are large (the phantom's tumour conforms).
#include "framework/core/Component.h"
#include "plugins/tetra_brain/TetraBrain.h"

namespace trephine::tetra {

class PlacedTumour final : public Component {
 public:
  static constexpr std::string_view kTypeName = "PlacedTumour";

  void init(InitContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;

 private:
  Link<TetraBrain> l_mesh{this, "mesh", {.help = "The brain the tumour is placed in", .required = true, .initOnly = true}};
  Field<Vec3> d_center{this, "center", Vec3::Zero(), {.help = "Centre of the tumour (world, after the brain's placement)", .unit = "mm", .required = true}};
  Field<double> d_radius{this, "radius", 8.0, {.help = "Radius of the tumour", .unit = "mm", .min = 0.0, .minExclusive = true}};
  Field<int> d_label{this, "label", 2, {.help = "The label its tetrahedra take (one the mesh does not use yet)"}};

  size_t m_tets = 0;
  double m_volume = 0;  // mm^3
};

}  // namespace trephine::tetra
