#include "plugins/tetra_brain/CubePhantom.h"

#include <stdexcept>
#include <string>

#include "framework/data/TetTopology.h"

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
  return makeBoxMesh({cells, cells, cells}, Vec3::Constant(-size / 2), Vec3::Constant(size / 2));
}

TetMesh makeBoxMesh(const std::array<int, 3>& cells, const Vec3& low, const Vec3& high) {
  for (int c : cells)
    if (c < 1 || c > 2000) throw std::invalid_argument("cells per axis must be in [1, 2000]");
  if (!((high - low).minCoeff() > 0)) throw std::invalid_argument("a box needs a positive size along every axis");
  const int nx = cells[0] + 1, ny = cells[1] + 1, nz = cells[2] + 1;  // nodes per axis
  const Vec3 h = (high - low).cwiseQuotient(Vec3(cells[0], cells[1], cells[2]));
  TetMesh mesh;
  mesh.nodes.reserve(size_t(nx) * ny * nz);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        // The far faces exactly at `high`, not at low + cells h (rounding).
        mesh.nodes.emplace_back(i == cells[0] ? high.x() : low.x() + i * h.x(),
                                j == cells[1] ? high.y() : low.y() + j * h.y(),
                                k == cells[2] ? high.z() : low.z() + k * h.z());
  auto node = [nx, ny](int i, int j, int k) { return int32_t(i + nx * (j + ny * k)); };
  mesh.tets.reserve(size_t(5) * cells[0] * cells[1] * cells[2]);
  for (int k = 0; k < cells[2]; ++k)
    for (int j = 0; j < cells[1]; ++j)
      for (int i = 0; i < cells[0]; ++i) {
        int32_t corner[8];
        for (int b = 0; b < 8; ++b) corner[b] = node(i + (b & 1), j + ((b >> 1) & 1), k + (b >> 2));
        const auto& split = (i + j + k) % 2 == 0 ? kEvenSplit : kOddSplit;
        for (const auto& t : split) mesh.tets.push_back({corner[t[0]], corner[t[1]], corner[t[2]], corner[t[3]]});
      }
  reorient(mesh);
  return mesh;
}

}  // namespace trephine::tetra
