#pragma once
// Holds nodes of a TLEDForceField's mesh at their rest positions: the nodes
// listed by index, the nodes inside a box, or the nodes of the elements of a
// tissue label (exactly one of the three). A passive component: it does its
// work once, at init, on the model.
#include <vector>

#include "framework/core/Component.h"
#include "plugins/fem/TLEDForceField.h"

namespace trephine::fem {

class FixedConstraint final : public Component {
 public:
  static constexpr std::string_view kTypeName = "FixedConstraint";

  void init(InitContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;

 private:
  Link<TLEDForceField> l_fem{this, "fem", {.help = "The FEM whose nodes this holds", .required = true}};
  Field<std::vector<double>> d_indices{
      this, "indices", {}, {.help = "Node indices (0-based, as in the mesh file's order)", .min = 0.0}};
  Field<std::vector<double>> d_box{
      this,
      "box",
      {},
      {.help = "xmin ymin zmin xmax ymax zmax: the nodes whose rest position is in this box", .unit = "mm"}};
  Field<int> d_label{
      this, "label", -1, {.help = "The nodes of every element with this tissue label (the mesh's labels)", .min = -1}};

  size_t m_fixed = 0;
};

}  // namespace trephine::fem
