#include "framework/data/CoarseVoxelGrid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace trephine {

CoarseVoxelGrid coarsenVoxels(const VoxelGrid& fine, int factor, VoxelPooling pooling) {
  if (factor < 1) throw std::invalid_argument("coarsenVoxels: the factor must be 1 or more");
  CoarseVoxelGrid out;
  out.factor = factor;
  VoxelGrid& g = out.grid;
  g = fine;
  g.nx = (fine.nx + factor - 1) / factor;
  g.ny = (fine.ny + factor - 1) / factor;
  g.nz = (fine.nz + factor - 1) / factor;
  g.spacing = fine.spacing * factor;
  g.inverseSpacing = g.spacing.cwiseInverse();
  out.codes.assign(g.voxelCount(), 0);
  for (int64_t K = 0; K < g.nz; ++K)
    for (int64_t J = 0; J < g.ny; ++J)
      for (int64_t I = 0; I < g.nx; ++I) {
        double sum = 0;
        VoxelCode most = std::numeric_limits<VoxelCode>::lowest();
        int n = 0;
        for (int64_t k = K * factor; k < std::min<int64_t>((K + 1) * factor, fine.nz); ++k)
          for (int64_t j = J * factor; j < std::min<int64_t>((J + 1) * factor, fine.ny); ++j)
            for (int64_t i = I * factor; i < std::min<int64_t>((I + 1) * factor, fine.nx); ++i, ++n) {
              const VoxelCode code = fine.codes[size_t(i + fine.nx * (j + int64_t(fine.ny) * k))];
              sum += code;
              most = std::max(most, code);
            }
        out.codes[size_t(I + g.nx * (J + int64_t(g.ny) * K))] =
            pooling == VoxelPooling::kMax ? most : VoxelCode(std::lround(sum / n));
      }
  g.codes = out.codes.data();
  return out;
}

}  // namespace trephine
