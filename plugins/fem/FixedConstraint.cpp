#include "plugins/fem/FixedConstraint.h"

#include <cmath>
#include <sstream>
#include <string>

#include "framework/core/Lifecycle.h"

namespace trephine::fem {

void FixedConstraint::init(InitContext& context) {
  const int chosen = int(d_indices.isSet()) + int(d_box.isSet()) + int(d_label.isSet());
  if (chosen != 1) {
    context.error(*this, "give exactly one of indices, box or label (" + std::to_string(chosen) + " given)");
    return;
  }
  TLEDForceField& fem = *l_fem;
  if (!fem.hasModel()) return;  // the FEM's own error is reported
  TLEDModel& model = fem.model();
  const size_t n = model.nodeCount();
  std::vector<char> selected(n, 0);
  if (d_indices.isSet()) {
    for (double index : d_indices.value()) {
      if (index != std::floor(index) || index >= double(n)) {
        std::ostringstream given;
        given << index;
        context.error(d_indices, "node " + given.str() + " is not a node index of a mesh of " +
                                     std::to_string(n) + " nodes (0 to " + std::to_string(n - 1) + ")");
        return;
      }
      selected[size_t(index)] = 1;
    }
  } else if (d_box.isSet()) {
    const std::vector<double>& b = d_box.value();
    if (b.size() != 6 || !(b[0] <= b[3] && b[1] <= b[4] && b[2] <= b[5])) {
      context.error(d_box, "expected six numbers, xmin ymin zmin xmax ymax zmax, each min <= its max");
      return;
    }
    const Box3 box(Vec3(b[0], b[1], b[2]), Vec3(b[3], b[4], b[5]));
    for (size_t i = 0; i < n; ++i) selected[i] = box.contains(model.restNodes()[i]) ? 1 : 0;
  } else {
    const TetMesh& mesh = fem.brain().mesh();
    if (mesh.labels.empty()) {
      context.error(d_label, "the mesh " + fem.brainPath() + " carries no tissue labels");
      return;
    }
    for (size_t e = 0; e < mesh.tetCount(); ++e)
      if (mesh.labels[e] == d_label.value())
        for (int32_t node : mesh.tets[e]) selected[node] = 1;
  }
  for (size_t i = 0; i < n; ++i)
    if (selected[i]) {
      model.fixNode(int32_t(i));
      ++m_fixed;
    }
  if (m_fixed == 0) {
    const BaseField& field = d_indices.isSet() ? static_cast<const BaseField&>(d_indices)
                             : d_box.isSet()   ? static_cast<const BaseField&>(d_box)
                                               : static_cast<const BaseField&>(d_label);
    context.error(field, "selects no node of " + fem.brainPath());
  }
}

void FixedConstraint::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"fixed_nodes", double(m_fixed)});
}

}  // namespace trephine::fem
