#pragma once
// The cost model of the tool's query on TetraBrain's grid
// (NativeTetBackend::locatePoints): chapter 5's method applied to a few
// hundred shell points against many tetrahedra. The query groups the shell's
// points by cell and, in each occupied cell,
//   reads the L tetrahedra the cell lists,
//   keeps the O of them whose box overlaps the box of the cell's points,
//   tests each of the cell's k points against each kept box (on a deforming
//   mesh, against those whose current box, read from the nodes, passes too),
// so a query costs
//   z(delta) = w_c C + w_l C L(delta) + w_o sum_cells O + w_p sum_cells k O.
// For a cell inside the mesh, with the tetrahedra spread evenly over its
// volume V, the expected number of boxes (extents A_t, grown by twice the
// displacement margin) that overlap an axis-aligned box of extents e is
//   N(e) = sum_t prod_i (A_ti + e_i) / V,
// so L = N(delta, delta, delta) and O = N(e) for the cell's points' box e.
// The occupied cells C and each one's k and e come from the shell itself,
// averaged over turns of the tool and shifts of the grid.
//   Small cells: every point has a cell of its own and reads the tetrahedra
//   around it, so z falls slowly towards C w_c + N L(0).
//   Large cells: the points share their cells' lists, but each point is
//   tested against every tetrahedron near its cell's points: sum k O grows
//   as delta^2.
// The minimiser scales with neither the mesh alone nor the tool alone: it
// is near the point spacing when the tetrahedra are much larger than it.
#include <span>
#include <vector>

#include "framework/data/TetMesh.h"

namespace trephine::tetra {

// Sums over the tetrahedra of the products of their box extents A, so that
// sum_t prod_i (A_ti + e_i) is a cubic in e read in constant time.
struct BoxProductSums {
  double xyz = 0;               // sum A_x A_y A_z (mm^3)
  Vec3 pairs = Vec3::Zero();    // (sum A_y A_z, sum A_x A_z, sum A_x A_y) (mm^2): the coefficients of e_x, e_y, e_z
  Vec3 singles = Vec3::Zero();  // (sum A_x, sum A_y, sum A_z) (mm)
};

// The mesh's part of the model.
struct TetBoxMoments {
  double volume = 0;      // mm^3, of the mesh (sum of the tetrahedra's)
  double tetrahedra = 0;  // count
  BoxProductSums grown;   // the grids' boxes: grown by the displacement margin on every side
  BoxProductSums tight;   // the tetrahedra's own boxes
  // Expected grown boxes overlapping an axis-aligned box of extents e (mm)
  // inside the mesh: the tetrahedra a cell lists (e = delta) and keeps.
  double overlapping(const Vec3& e) const;
  // The same for the tight boxes: on a deforming mesh, the kept tetrahedra
  // whose current box passes the points' box, whose points are tested.
  double tightOverlapping(const Vec3& e) const;
};
// `margin` (mm): the grids' displacement margin (0 for a rigid mesh).
TetBoxMoments measureBoxMoments(const TetMesh& mesh, double margin);

// The work of one query (counts), as NativeTetBackend::LocateWork counts it.
struct ToolQueryWork {
  double cells = 0, listed = 0, overlapping = 0, pointTests = 0;
};

// The time of each term (ns), fitted to the tool query's experiment with
// non-negative least squares, all meshes of docs/results.md at once (one
// constant per mesh besides). Only the minimiser matters: the weights'
// ratios, not the machine's speed.
struct ToolQueryWeights {
  double cell = 0;         // w_c: an occupied cell (its list's start, the points' box)
  double listed = 0;       // w_l: a tetrahedron a cell lists (its box against the points' box)
  double overlapping = 0;  // w_o: a kept tetrahedron (on a deforming mesh, its current box: 4 node reads)
  double pointTest = 0;    // w_p: a point against a kept box
};
// A rigid mesh: the listed tetrahedra cost nothing the cells do not explain
// (their counts rise together); a cell costs ten point tests.
constexpr ToolQueryWeights kRigidToolQueryWeights{27.6, 0.0, 0.0, 2.67};
// A deforming mesh: every kept tetrahedron reads its nodes' current positions.
constexpr ToolQueryWeights kDeformingToolQueryWeights{52.5, 3.61, 10.2, 2.29};

// The expected work of locating `shell` (tool frame, mm) with cells of side
// `delta` (mm), every occupied cell inside the mesh; averaged over `samples`
// turns of the tool and shifts of the grid (the same ones at every delta).
ToolQueryWork predictToolQueryWork(const TetBoxMoments& moments, std::span<const Vec3> shell, double delta,
                                   int samples = 16);
double toolQueryCost(const ToolQueryWork& work, const ToolQueryWeights& weights);

// The smallest cell searched, in average edges. The model counts work, not
// memory: with each point in a cell of its own, smaller cells only list
// fewer tetrahedra, and it would shrink the cells without end for a large
// tool on a fine mesh. Below a quarter edge the grid lists each tetrahedron
// in some 70 cells (about 300 bytes per tetrahedron, against 70 at half an
// edge), and the measured queries slow down as its cells fall out of cache,
// which the constant weights do not see (docs/results.md: on the rigid
// brains the measured optimum is 0.2 to 0.35 edges, the model's 0.1 to 0.2).
constexpr double kSmallestCellInEdges = 0.25;

// The delta (mm) minimising the summed cost of the shells' queries, searched
// from kSmallestCellInEdges to four times the mesh's average edge
// `averageEdge` (mm).
double optimalToolCellSize(const TetBoxMoments& moments, std::span<const std::vector<Vec3>> shells,
                           double averageEdge, const ToolQueryWeights& weights);

}  // namespace trephine::tetra
