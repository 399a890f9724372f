// libFuzzer target: arbitrary bytes as a sequence of removals from a brain
// (resection). The first byte picks the box mesh (2 to 5 cells a side, 40 to
// 625 tetrahedra); the rest, two bytes at a time, are tetrahedra to remove
// (any index, repeats and removed ones too), a 0xFFFF pair closing a batch.
// Each batch goes through BrainResection (which takes the pieces, flaps and
// spikes it leaves), the native back-end and a TLED model, as a frame does.
// After each: the remaining mesh's invariants hold, the back-end finds the
// centroid of every alive tetrahedron in it and of no removed one, and the
// FEM stays finite over a few steps. Any crash, sanitizer report or broken
// invariant is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "plugins/fem/TLEDModel.h"
#include "plugins/fem/TLEDState.h"
#include "plugins/tetra_brain/BrainResection.h"
#include "plugins/tetra_brain/CubePhantom.h"
#include "plugins/tetra_brain/NativeTetBackend.h"

using namespace trephine;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const int cells = 2 + data[0] % 4;
  TetMesh mesh = tetra::makeBoxMesh({cells, cells, cells}, Vec3::Zero(), Vec3(10.0 * cells, 10.0 * cells, 10.0 * cells));
  mesh.labels.assign(mesh.tetCount(), 1);
  const TetTopology topology(mesh);
  tetra::TissueTable tissues;
  if (tissues.declare({"brain", 1, 0.05, 0.03, false}, mesh.labels)) std::abort();
  tetra::BrainResection resection(mesh, topology, tissues);
  tetra::NativeTetBackend backend;
  backend.bind({&mesh, &topology, {}});
  if (backend.followRemovals()) std::abort();
  const fem::ElementMaterial material{1e-6, 30.0, 0.3};
  fem::TLEDModel model(mesh.nodes, mesh.tets, std::span(&material, 1));
  model.setTimeStep(0.5 * model.criticalTimeStep(), 50);
  fem::TLEDState state(model);
  std::vector<Vec3> positions(mesh.nodeCount());
  std::vector<int32_t> batch, elements;
  auto apply = [&] {
    resection.queue(batch);
    batch.clear();
    for (RemainingMesh::Change c = resection.removeNext(); !c.removedTets.empty(); c = resection.removeNext()) {
      backend.removeTets(c);
      elements.assign(c.removedTets.begin(), c.removedTets.end());
      model.removeElements(elements);
    }
    const RemainingMesh& left = resection.remaining();
    if (!left.validate().empty()) std::abort();
    for (int32_t t = 0; t < int32_t(mesh.tetCount()); ++t) {
      Vec3 c = Vec3::Zero();
      for (int32_t n : mesh.tets[size_t(t)]) c += mesh.nodes[size_t(n)];
      const int32_t found = backend.locate(c / 4);
      if (left.alive(t) ? found != t : found != -1) std::abort();
    }
    state.clearExternalForces();
    for (size_t n = 0; n < mesh.nodeCount(); n += 3)
      if (left.nodeUse(int32_t(n)) > 0) state.setExternalForce(int32_t(n), Vec3(5, -3, 20));
    for (int s = 0; s < 5; ++s) state.step();
    if (!std::isfinite(state.writePositions(positions).largestDisplacement)) std::abort();
  };
  for (size_t i = 1; i + 1 < size; i += 2) {
    const int value = data[i] | (data[i + 1] << 8);
    if (value == 0xFFFF) {
      apply();
      continue;
    }
    batch.push_back(int32_t(value % (int(mesh.tetCount()) + 8)) - 4);  // a few out of range
  }
  apply();
  return 0;
}
