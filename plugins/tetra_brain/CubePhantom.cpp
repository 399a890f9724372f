#include "plugins/tetra_brain/CubePhantom.h"

#include <stdexcept>
#include <string>

#include "plugins/tetra_brain/TetTopology.h"

namespace trephine::tetra {

namespace {
// Corner b of a cell is at (b & 1, (b >> 1) & 1, b >> 2). Five tetrahedra: four
// cut off at alternate corners and the one in the middle; the odd split is the
// even one mirrored, so the diagonals of shared faces agree.
constexpr int kEvenSplit[5][4] = {{0, 1, 2, 4}, {3, 2, 1, 7}, {5, 4, 7, 1}, {6, 7, 4, 2}, {1, 2, 4, 7}};
constexpr int kOddSplit[5][4] = {{1, 0, 3, 5}, {2, 3, 0, 6}, {4, 5, 6, 0}, {7, 6, 5, 3}, {0, 3, 5, 6}};
}  // namespace

TetMesh makeCubeMesh(int cells, double size) {
  if (cells < 1 || cells > 200)
    throw std::invalid_argument("cells must be in [1, 200] (" + std::to_string(cells) + " given)");
  if (!(size > 0)) throw std::invalid_argument("cube size must be > 0 mm");
  const int n = cells + 1;  // nodes per axis
  const double h = size / cells;
  TetMesh mesh;
  mesh.nodes.reserve(size_t(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) mesh.nodes.emplace_back(i * h - size / 2, j * h - size / 2, k * h - size / 2);
  auto node = [n](int i, int j, int k) { return int32_t(i + n * (j + n * k)); };
  mesh.tets.reserve(size_t(5) * cells * cells * cells);
  for (int k = 0; k < cells; ++k)
    for (int j = 0; j < cells; ++j)
      for (int i = 0; i < cells; ++i) {
        int32_t corner[8];
        for (int b = 0; b < 8; ++b) corner[b] = node(i + (b & 1), j + ((b >> 1) & 1), k + (b >> 2));
        const auto& split = (i + j + k) % 2 == 0 ? kEvenSplit : kOddSplit;
        for (const auto& t : split) mesh.tets.push_back({corner[t[0]], corner[t[1]], corner[t[2]], corner[t[3]]});
      }
  reorient(mesh);
  return mesh;
}

}  // namespace trephine::tetra
