#pragma once
// Resection of a brain's tissues: the owner of what removing tissue from one
// TetraBrain does and measures. Placed after the brain's Tissue components
// (it reads the tissues they declared): a brain with no tissue declared is
// an error here, and labels of the mesh that no tissue declares are warned
// of by number (their tetrahedra stay brain, deform and are touched, but no
// tool removes them). Reports each tissue's volume at rest (mm^3).
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

 private:
  Link<TetraBrain> l_mesh{
      this, "mesh", {.help = "The brain whose tissues are resected (place this after its Tissue components)",
                     .required = true, .initOnly = true}};

  // Per tissue (declaration order): its name and volume at rest (mm^3).
  std::vector<std::pair<std::string, double>> m_volumes;
};

}  // namespace trephine::tetra
