// The cell-size cost model (thesis chapter 5) against closed forms and the
// thesis's own tables; the experiment's error measure (Eq. 5.9) against the
// thesis's printed errors.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "plugins/tetra_brain/CubePhantom.h"
#include "plugins/tetra_brain/cell_size/CellSizeExperiment.h"
#include "plugins/tetra_brain/cell_size/CellSizeModel.h"

namespace trephine::tetra {
namespace {

TEST(CellSizeModelTest, OneTetrahedronsInputsAreItsEdgesAndFacets) {
  // Edges 1, 1, 1 (along the axes) and sqrt 2 (three face diagonals); three
  // right triangles of area 1/2 and one equilateral of side sqrt 2.
  const TetMesh mesh{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}, {{0, 1, 2, 3}}, {}};
  const CellSizeInputs in = measureCellSizeInputs(mesh);
  EXPECT_EQ(in.edges, 6u);
  EXPECT_EQ(in.facets, 4u);
  EXPECT_NEAR(in.averageEdge, (3 + 3 * std::sqrt(2.0)) / 6, 1e-15);
  EXPECT_NEAR(in.longestEdge, std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(in.facetArea, (1.5 + std::sqrt(3.0) / 2) / 4, 1e-15);
}

TEST(CellSizeModelTest, AFacetOrAnEdgeTwoTetrahedraShareCountsOnce) {
  // A second tetrahedron on the slanted facet: 9 edges, 7 facets.
  const TetMesh mesh{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(1, 1, 1)},
                     {{0, 1, 2, 3}, {1, 2, 3, 4}},
                     {}};
  const CellSizeInputs in = measureCellSizeInputs(mesh);
  EXPECT_EQ(in.edges, 9u);
  EXPECT_EQ(in.facets, 7u);
  // Edges: 3 of 1 and 6 of sqrt 2 (the new node is sqrt 2 from nodes 1, 2, 3).
  EXPECT_NEAR(in.averageEdge, (3 + 6 * std::sqrt(2.0)) / 9, 1e-15);
  // Facets: 3 right triangles and 4 equilateral ones of side sqrt 2.
  EXPECT_NEAR(in.facetArea, (1.5 + 4 * std::sqrt(3.0) / 2) / 7, 1e-15);
}

TEST(CellSizeModelTest, AMeshWithoutTetrahedraIsRefused) {
  EXPECT_THROW(measureCellSizeInputs(TetMesh{}), std::invalid_argument);
  const TetMesh flat{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)}, {{0, 1, 2, 3}}, {}};
  EXPECT_THROW(measureCellSizeInputs(flat), std::invalid_argument);
}

// For regular tetrahedra of edge a (s = a, A_t = sqrt(3)/4 a^2), p_nc 0.99
// and r_t 5, dz/ddelta = 0 is 1.2 x^3 - 0.3 x^2 - 2.97 = 0 in x = delta / a:
// Cardano's root, independently of the model's bisection.
TEST(CellSizeModelTest, RegularTetrahedraGiveCardanosRootOfTheOptimalityCubic) {
  const double a = 3.7;
  CellSizeInputs in;
  in.longestEdge = a;
  in.facetArea = std::sqrt(3.0) / 4 * a * a;
  // x^3 + b x^2 + d = 0 with b = -0.25, d = -2.475; x = y - b/3.
  const double b = -0.25, d = -2.475;
  const double p = -b * b / 3, q = 2 * b * b * b / 27 + d;
  const double disc = std::sqrt(q * q / 4 + p * p * p / 27);
  const double y = std::cbrt(-q / 2 + disc) + std::cbrt(-q / 2 - disc);
  const double expected = (y - b / 3) * a;
  EXPECT_NEAR(optimalCellSize(in, {}), expected, 1e-9 * expected);
  EXPECT_NEAR(expected / a, 1.44, 0.01);  // the thesis's tables: delta_a about 1.43 to 1.46 edges
}

TEST(CellSizeModelTest, TheOptimumMinimisesTheCostAndScalesWithTheMesh) {
  const TetMesh mesh = makeCubeMesh(5, 100.0);
  const CellSizeInputs in = measureCellSizeInputs(mesh);
  const CostParameters parameters{0.98, 7};
  const double best = optimalCellSize(in, parameters);
  const double z = relativeCost(in, parameters, best);
  for (double factor : {0.9, 0.99, 1.01, 1.1}) EXPECT_GT(relativeCost(in, parameters, best * factor), z);
  // Three times larger: the same mesh in other units.
  TetMesh larger = mesh;
  for (Vec3& p : larger.nodes) p *= 3;
  EXPECT_NEAR(optimalCellSize(measureCellSizeInputs(larger), parameters), 3 * best, 1e-9 * best);
  EXPECT_THROW(optimalCellSize(in, {1.0, 5}), std::invalid_argument);
  EXPECT_THROW(optimalCellSize(in, {0.99, 0}), std::invalid_argument);
}

// Eq. 5.9 on the thesis's Tables 5.2 and 5.4 (voxels per axis of a 4 mm
// scene: a cell of 4 / N) against its Tables 5.3 and 5.5.
TEST(CellSizeModelTest, TheErrorMeasureReproducesTheThesissTables) {
  struct Row {
    double nMin, nOpt, nMax, nA, nTrad, errorA, errorTrad;
  };
  const Row rows[] = {{20, 28.33, 39, 28.73, 41.90, 0.038, 1.272}, {22, 28.16, 38, 30.94, 45.16, 0.283, 1.727},
                      {16, 34.04, 54, 32.49, 47.40, 0.086, 0.669}, {8, 26.63, 47, 34.48, 50.29, 0.385, 1.162},
                      {20, 37.87, 57, 35.65, 51.90, 0.124, 0.734}, {16, 22.97, 34, 31.35, 44.94, 0.759, 1.992},
                      {13, 31.15, 54, 48.80, 70.93, 0.772, 1.741}, {13, 20.49, 37, 31.55, 45.48, 0.669, 1.516}};
  for (const Row& r : rows) {
    // The larger N is the smaller cell: the zone's low cell is 4 / nMax.
    const double low = 4 / r.nMax, optimal = 4 / r.nOpt, high = 4 / r.nMin;
    // The tables' inputs are rounded to 0.01: the errors follow to about 0.002.
    EXPECT_NEAR(cellSizeError(optimal, low, high, 4 / r.nA), r.errorA, 0.003) << r.nOpt;
    EXPECT_NEAR(cellSizeError(optimal, low, high, 4 / r.nTrad), r.errorTrad, 0.003) << r.nOpt;
  }
  EXPECT_EQ(cellSizeError(2.0, 1.0, 3.0, 2.0), 0.0);
  EXPECT_NEAR(cellSizeError(2.0, 1.0, 3.0, 3.0), 1.0, 1e-15);  // the zone's edges
  EXPECT_NEAR(cellSizeError(2.0, 1.0, 3.0, 1.0), 1.0, 1e-15);
  // An optimum at the end of the sampled range (the zone's larger cell is the
  // optimum itself): that side is taken as wide as the other, not infinite.
  // In cells per mm the zone is then [1/2, 1] around 1/2: width 1/2 on the
  // smaller-cell side.
  EXPECT_NEAR(cellSizeError(2.0, 1.0, 2.0, 4.0), (0.5 - 0.25) / 0.5, 1e-15);
  EXPECT_NEAR(cellSizeError(2.0, 1.0, 2.0, 1.0), (1.0 - 0.5) / 0.5, 1e-15);
}

}  // namespace
}  // namespace trephine::tetra
