#pragma once
// Collision between two tetrahedral meshes through a uniform grid (thesis
// section 5.2, after Teschner et al. 2003). Every frame the particles
// (vertices) of one object are sorted into the grid's cells; each
// tetrahedron of the other takes its box on its current nodes, visits the
// cells the box overlaps (its objective voxels), tests the particles listed
// there against the box and those inside it against the tetrahedron
// (barycentric coordinates). The loops are the ones the cell-size model
// (CellSizeModel.h) counts.
#include <cstdint>
#include <span>
#include <vector>

#include "framework/math/Math.h"
#include "framework/data/TetMesh.h"

namespace trephine::tetra {

// Points sorted into cubic cells (compressed rows, a counting sort): built
// every frame, reusing its memory.
class ParticleGrid {
 public:
  // Cells of side `cellSize` (mm) from `bounds.min()` over `bounds`. Throws
  // std::invalid_argument when that takes more than `maxCells` cells.
  void build(std::span<const Vec3> points, const Box3& bounds, double cellSize, size_t maxCells = size_t(1) << 25);
  // The cell range a box overlaps, clamped to the grid; false if it misses.
  bool cellRange(const Box3& box, std::array<int32_t, 3>& lo, std::array<int32_t, 3>& hi) const;
  std::span<const int32_t> particles(int32_t i, int32_t j, int32_t k) const {
    const size_t cell = size_t(i) + size_t(m_dims[0]) * (size_t(j) + size_t(m_dims[1]) * size_t(k));
    return {m_items.data() + m_start[cell], m_items.data() + m_start[cell + 1]};
  }
  double cellSide() const { return m_side; }
  size_t cellCount() const { return m_start.empty() ? 0 : m_start.size() - 1; }

 private:
  Vec3 m_origin = Vec3::Zero();
  double m_side = 1;
  std::array<int32_t, 3> m_dims{0, 0, 0};
  std::vector<uint32_t> m_start;  // cellCount + 1 offsets into m_items
  std::vector<int32_t> m_items;   // particle indices by cell
  std::vector<int32_t> m_cellOf;  // per particle, during the build
};

// What one detection did: the loops of the cost model.
struct PairCounts {
  uint64_t cellVisits = 0;        // objective voxels visited (v_o per tetrahedron)
  uint64_t boxTests = 0;          // particles tested against a tetrahedron's box
  uint64_t barycentricTests = 0;  // of those, inside the box
  uint64_t contacts = 0;          // particle-in-tetrahedron pairs found
  uint64_t tetsWithParticles = 0; // tetrahedra whose cells held a particle (the "colliding" ones of the model)
  uint64_t collidingTets = 0;     // tetrahedra holding a particle
  PairCounts& operator+=(const PairCounts& o);
};

struct ParticleInTet {
  int32_t particle;
  int32_t tet;
  double weights[4];  // barycentric coordinates of the particle in the tetrahedron
};

// The particles (indices into `particles`, sorted in `grid`) inside the
// tetrahedra `tets` on `nodes`; appended to `found`. `boxes` is scratch, one
// per tetrahedron (the boxes on the current nodes: the first pass).
PairCounts findParticlesInTets(std::span<const Vec3> nodes, std::span<const TetIndices> tets,
                               std::span<const Vec3> particles, const ParticleGrid& grid, std::vector<Box3>& boxes,
                               std::vector<ParticleInTet>& found);

// Two meshes moving as rigid bodies (translations only) with a penalty
// response: the experiment's scene. Each frame the particles of B are found
// in the tetrahedra of A, and each pushes B away from A (and A the other way)
// along the line of their centres with a force stiffness x depth, the depth
// its distance to the nearest facet of its tetrahedron.
class TetPairScene {
 public:
  TetPairScene(const TetMesh& a, const TetMesh& b, const Vec3& offsetOfB);
  // One frame: detection at `cellSize` (mm), then the response over `dt` (s).
  PairCounts step(double cellSize, double dt);
  // Detection only, on the current positions.
  PairCounts detect(double cellSize);
  void setVelocityOfB(const Vec3& velocity) { m_velocityB = velocity; }
  double stiffness = 1.0;  // N/mm of depth per particle
  double massA = 1, massB = 1;  // kg
  const Vec3& offsetOfB() const { return m_offsetB; }
  const Vec3& offsetOfA() const { return m_offsetA; }

 private:
  const TetMesh& m_a;
  const TetMesh& m_b;
  Vec3 m_offsetA = Vec3::Zero(), m_offsetB, m_velocityA = Vec3::Zero(), m_velocityB = Vec3::Zero();
  std::vector<Vec3> m_nodesA, m_particlesB;
  std::vector<Box3> m_boxes;
  std::vector<ParticleInTet> m_found;
  ParticleGrid m_grid;
};

}  // namespace trephine::tetra
