// Meshing a labelled image with CGAL Mesh_3's labelled image domain
// (`trephine mesh LABELS`): a 256^3 segmentation at 0.8 mm (the brain
// phantom's shape, label 1, with two ventricle-like ellipsoids, label 2) to
// about 50,000 tetrahedra, the whole call (count iterations and sliver
// removal included). The smoke test meshes 48^3 at 4 mm to 2,000.
#include <benchmark/benchmark.h>

#include <cstdlib>

#include "plugins/tetra_brain/BrainPhantom.h"
#include "framework/meshing/TetMeshing.h"

namespace {

using trephine::Vec3;
using trephine::LabelledImage;
using trephine::meshLabelledImage;

bool smoke() { return std::getenv("TREPHINE_BENCH_LABELLED_MESH_SMOKE") != nullptr; }

LabelledImage segmentation(int side, double voxel) {
  LabelledImage image;
  image.dims = {side, side, side};
  image.spacing = Vec3::Constant(voxel);
  image.origin = Vec3::Constant(-0.5 * (side - 1) * voxel);
  image.labels.resize(size_t(side) * side * side);
  size_t n = 0;
  for (int k = 0; k < side; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i, ++n) {
        const Vec3 p = image.origin + voxel * Vec3(i, j, k);
        if (trephine::tetra::brainPhantomDistance(p) >= 0) continue;
        // Ventricles: an ellipsoid in each hemisphere (mm).
        const Vec3 q(std::abs(p.x()) - 14, p.y() + 5, p.z() - 5);
        const bool ventricle = (q.cwiseQuotient(Vec3(8, 30, 10))).squaredNorm() < 1;
        image.labels[n] = ventricle ? 2 : 1;
      }
  return image;
}

void BM_MeshLabelledImage(benchmark::State& state) {
  const int side = smoke() ? 48 : 256, target = smoke() ? 2000 : int(state.range(0));
  const LabelledImage image = segmentation(side, smoke() ? 4.0 : 0.8);
  size_t tets = 0;
  for (auto _ : state) {
    const trephine::TetMesh mesh = meshLabelledImage(image, target);
    tets = mesh.tetCount();
  }
  state.counters["voxels"] = double(image.labels.size());
  state.counters["tets"] = double(tets);
  state.counters["target"] = target;
}
BENCHMARK(BM_MeshLabelledImage)->Arg(50000)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1)->Repetitions(3);

}  // namespace

BENCHMARK_MAIN();
