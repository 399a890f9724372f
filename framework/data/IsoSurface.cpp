#include "framework/data/IsoSurface.h"

#include <algorithm>
#include <unordered_map>

namespace trephine {

namespace {

// Corner c of a cell is (c & 1, (c >> 1) & 1, c >> 2) from its base corner.
// The 6 tetrahedra around the diagonal 0-7: every face of the cell is split
// along the same diagonal as the neighbouring cell's face, so the surface is
// consistent across cells.
constexpr int kTetrahedra[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};

struct CellCorners {
  double value[8];
  Vec3 position[8];
  uint64_t id[8];  // in the padded corner grid: the same corner has the same id in every cell
};

class BlockExtractor {
 public:
  BlockExtractor(const VoxelGrid& grid, TriangleMesh& mesh, uint64_t& degenerate)
      : m_grid(grid), m_mesh(mesh), m_degenerate(degenerate) {}

  void cell(int64_t i, int64_t j, int64_t k) {
    CellCorners c;
    bool anyInside = false, anyOutside = false;
    for (int n = 0; n < 8; ++n) {
      const int64_t a = i + (n & 1), b = j + ((n >> 1) & 1), d = k + (n >> 2);
      c.value[n] = m_grid.codeAtCell(a, b, d);
      const bool inside = c.value[n] > m_grid.isoCode;
      anyInside |= inside;
      anyOutside |= !inside;
      c.position[n] =
          m_grid.corner + Vec3((double(a) + 0.5) * m_grid.spacing.x(), (double(b) + 0.5) * m_grid.spacing.y(),
                               (double(d) + 0.5) * m_grid.spacing.z());
      c.id[n] =
          uint64_t(a + 1) + uint64_t(m_grid.nx + 2) * (uint64_t(b + 1) + uint64_t(m_grid.ny + 2) * uint64_t(d + 1));
    }
    if (!anyInside || !anyOutside) return;
    for (const auto& tet : kTetrahedra) tetrahedron(c, tet);
  }

 private:
  // The vertex where the isosurface crosses the edge between corners p and q
  // (one inside, one outside), computed from the lower id to the higher so
  // every cell and block sharing the edge gets the same coordinates.
  int32_t edgeVertex(const CellCorners& c, int p, int q) {
    if (c.id[p] > c.id[q]) std::swap(p, q);
    const uint64_t key = (c.id[p] << 32) | c.id[q];
    const auto [it, added] = m_vertices.try_emplace(key, int32_t(m_mesh.vertices.size()));
    if (added) {
      const double t = (m_grid.isoCode - c.value[p]) / (c.value[q] - c.value[p]);
      m_mesh.vertices.push_back(c.position[p] + t * (c.position[q] - c.position[p]));
    }
    return it->second;
  }

  // Adds the triangle facing `outward` (from the inside corners to the outside ones).
  void triangle(int32_t a, int32_t b, int32_t c, const Vec3& outward) {
    const Vec3& pa = m_mesh.vertices[size_t(a)];
    const Vec3 normal = (m_mesh.vertices[size_t(b)] - pa).cross(m_mesh.vertices[size_t(c)] - pa);
    if (!(normal.squaredNorm() > 0)) {
      ++m_degenerate;
      return;
    }
    if (normal.dot(outward) < 0) std::swap(b, c);
    m_mesh.triangles.push_back({a, b, c});
  }

  void tetrahedron(const CellCorners& c, const int (&tet)[4]) {
    int in[4], out[4], inside = 0, outside = 0;
    for (const int n : tet) (c.value[n] > m_grid.isoCode ? in[inside++] : out[outside++]) = n;
    if (inside == 0 || outside == 0) return;
    Vec3 outward = Vec3::Zero();
    for (int n = 0; n < outside; ++n) outward += c.position[out[n]] / outside;
    for (int n = 0; n < inside; ++n) outward -= c.position[in[n]] / inside;
    if (inside == 1 || outside == 1) {
      // One corner apart from the other three: one triangle around it.
      const int lone = inside == 1 ? in[0] : out[0];
      const int* others = inside == 1 ? out : in;
      triangle(edgeVertex(c, lone, others[0]), edgeVertex(c, lone, others[1]), edgeVertex(c, lone, others[2]), outward);
      return;
    }
    // Two and two: a quad, as two triangles.
    const int32_t ac = edgeVertex(c, in[0], out[0]), ad = edgeVertex(c, in[0], out[1]);
    const int32_t bd = edgeVertex(c, in[1], out[1]), bc = edgeVertex(c, in[1], out[0]);
    triangle(ac, ad, bd, outward);
    triangle(ac, bd, bc, outward);
  }

  const VoxelGrid& m_grid;
  TriangleMesh& m_mesh;
  uint64_t& m_degenerate;
  std::unordered_map<uint64_t, int32_t> m_vertices;  // edge (lower id, higher id) to vertex
};

}  // namespace

void BlockedIsoSurface::build(const VoxelGrid& grid, const CellsWithoutSurface& skip) {
  m_cells = {int64_t(grid.nx) + 1, int64_t(grid.ny) + 1, int64_t(grid.nz) + 1};
  for (int a = 0; a < 3; ++a) m_blocksPerAxis[a] = (m_cells[a] + kBlockCells - 1) / kBlockCells;
  m_blocks.assign(size_t(m_blocksPerAxis[0] * m_blocksPerAxis[1] * m_blocksPerAxis[2]), TriangleMesh{});
  m_degenerate = 0;
  for (size_t b = 0; b < m_blocks.size(); ++b) extractBlock(grid, b, skip);
}

std::vector<size_t> BlockedIsoSurface::update(const VoxelGrid& grid, const std::array<int64_t, 3>& first,
                                              const std::array<int64_t, 3>& last, const CellsWithoutSurface& skip) {
  std::vector<size_t> changed;
  forBlocksTouching(first, last, [&](size_t b) { changed.push_back(b); });
  reextract(grid, changed, skip);
  return changed;
}

void BlockedIsoSurface::reextract(const VoxelGrid& grid, std::span<const size_t> blocks,
                                  const CellsWithoutSurface& skip) {
  for (const size_t b : blocks) extractBlock(grid, b, skip);
}

void BlockedIsoSurface::extractBlock(const VoxelGrid& grid, size_t index, const CellsWithoutSurface& skip) {
  TriangleMesh& mesh = m_blocks[index];
  mesh.vertices.clear();
  mesh.triangles.clear();
  const int64_t bx = int64_t(index) % m_blocksPerAxis[0];
  const int64_t by = (int64_t(index) / m_blocksPerAxis[0]) % m_blocksPerAxis[1];
  const int64_t bz = int64_t(index) / (m_blocksPerAxis[0] * m_blocksPerAxis[1]);
  BlockExtractor extractor(grid, mesh, m_degenerate);
  for (int64_t k = bz * kBlockCells - 1; k < std::min((bz + 1) * kBlockCells, m_cells[2]) - 1; ++k)
    for (int64_t j = by * kBlockCells - 1; j < std::min((by + 1) * kBlockCells, m_cells[1]) - 1; ++j)
      for (int64_t i = bx * kBlockCells - 1; i < std::min((bx + 1) * kBlockCells, m_cells[0]) - 1; ++i) {
        if (skip && skip(i, j, k)) continue;
        extractor.cell(i, j, k);
      }
}

TriangleMesh BlockedIsoSurface::merged() const {
  TriangleMesh all;
  for (const TriangleMesh& b : m_blocks) {
    const int32_t offset = int32_t(all.vertices.size());
    all.vertices.insert(all.vertices.end(), b.vertices.begin(), b.vertices.end());
    for (const auto& t : b.triangles) all.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  }
  return all;
}

}  // namespace trephine
