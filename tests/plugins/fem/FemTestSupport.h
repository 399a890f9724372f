#pragma once
// What the FEM's tests share: the thesis's brain material and a model of a mesh.
#include <span>

#include "plugins/fem/TLEDModel.h"
#include "framework/data/TetMesh.h"

namespace trephine::fem::test {

inline constexpr ElementMaterial kBrain{1e-6, 30.0, 0.3};  // Table 6.1

inline TLEDModel modelOf(const TetMesh& mesh, const ElementMaterial& material = kBrain) {
  return TLEDModel(mesh.nodes, mesh.tets, std::span(&material, 1));
}

}  // namespace trephine::fem::test
