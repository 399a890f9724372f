#pragma once
// The cost model of uniform-grid collision detection between tetrahedral
// meshes (thesis chapter 5, after Borro et al. 2004): the time to find which
// particles (vertices) of one object lie in which tetrahedra of another,
// per tetrahedron and in units of the time to look at one empty cell,
//   z(delta) = v_o (p_nc + (1 - p_nc) r_t p_v),
// three nested loops: each tetrahedron visits the v_o cells its box overlaps
// (objective voxels), and in a colliding one (probability 1 - p_nc) tests the
// p_v particles each holds, a test r_t times dearer than a cell visit.
//   v_o = (s / delta + 2)^3   (s: the side of a tetrahedron's box in the
//                              worst orientation, its longest edge)
//   p_v = 3 sqrt(3) delta^2 / (2 A_t)   (three particles per facet; the
//                              largest triangle in a cell, sqrt(3)/2 delta^2,
//                              over the mean facet area A_t)
// The thesis writes v_o with a ceiling; the ceiling makes z a staircase whose
// derivative never vanishes, so the minimiser here is that of the continuous
// form: the positive root of 4 q delta^3 - s q delta^2 - 3 s p_nc = 0 with
// q = (1 - p_nc) r_t 3 sqrt(3) / (2 A_t), about 1.44 edge lengths for
// regular tetrahedra. It scales with the mesh: a mesh twice as large has a
// cell twice as large.
#include <cstddef>

#include "framework/data/TetMesh.h"

namespace trephine::tetra {

// What the model reads from a mesh (lengths mm, areas mm^2).
struct CellSizeInputs {
  double longestEdge = 0;  // s: the mean over tetrahedra of each one's longest edge
  double largestEdge = 0;  // the longest edge of the mesh
  double facetArea = 0;    // A_t: the mean area of the distinct triangles (a shared facet once)
  double averageEdge = 0;  // the mean length of the distinct edges: the traditional cell size (Teschner et al.)
  size_t tetrahedra = 0, facets = 0, edges = 0;
};
// Throws std::invalid_argument for a mesh with no tetrahedra or degenerate ones only.
CellSizeInputs measureCellSizeInputs(const TetMesh& mesh);

struct CostParameters {
  double collisionFreeProbability = 0.99;  // p_nc: a tetrahedron holds none of the other's particles
  double testTimeRatio = 5;                // r_t: a particle test over a cell visit
};

// z(delta), delta the cell side (mm).
double relativeCost(const CellSizeInputs& inputs, const CostParameters& parameters, double delta);
// The delta (mm) that minimises z.
double optimalCellSize(const CellSizeInputs& inputs, const CostParameters& parameters);

}  // namespace trephine::tetra
