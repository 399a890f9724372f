#pragma once
// What the FEM's tests share: the thesis's brain material and a model of a mesh.
#include <span>

#include "plugins/fem/TledModel.h"
#include "framework/data/TetMesh.h"

namespace trephine::fem::test {

inline constexpr ElementMaterial kBrain{1e-6, 30.0, 0.3};  // Table 6.1

inline TledModel modelOf(const TetMesh& mesh, const ElementMaterial& material = kBrain) {
  return TledModel(mesh.nodes, mesh.tets, std::span(&material, 1));
}

}  // namespace trephine::fem::test
