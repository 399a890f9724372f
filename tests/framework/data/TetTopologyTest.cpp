// Topology, validation and the cube phantom of tetrahedral meshes.
#include <gtest/gtest.h>

#include "plugins/tetra_brain/CubePhantom.h"
#include "framework/data/TetTopology.h"
#include "plugins/tetra_brain/UniformGrid.h"

namespace trephine::tetra {
namespace {

TetMesh twoTets() {
  // Two tets sharing the face (0, 1, 2).
  TetMesh m;
  m.nodes = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)};
  m.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}};
  return m;
}

TEST(TetTopologyTest, CubeModelsOfTable41) {
  for (const int cells : {1, 7, 13}) {
    const TetMesh cube = makeCubeMesh(cells);
    EXPECT_EQ(cube.tetCount(), size_t(5) * cells * cells * cells);
    const TetTopology topology(cube);
    const MeshReport report = inspectMesh(cube, topology);
    EXPECT_EQ(report.describe(), "") << cells << " cells";
    EXPECT_GT(report.minVolume, 0.0);
    // Every cell face on the cube's surface is split into two triangles.
    EXPECT_EQ(topology.boundaryFaces().size(), size_t(12) * cells * cells) << "faces of neighbouring cells match";
    double volume = 0;
    for (const TetIndices& t : cube.tets)
      volume += signedVolume(cube.nodes[t[0]], cube.nodes[t[1]], cube.nodes[t[2]], cube.nodes[t[3]]);
    EXPECT_NEAR(volume, 200.0 * 200.0 * 200.0, 1e-3);
  }
  EXPECT_EQ(makeCubeMesh(60).tetCount(), 1080000u);
}

TEST(TetTopologyTest, NeighboursAcrossTheSharedFaceAndBoundaryFacesPointOut) {
  const TetMesh m = twoTets();
  const TetTopology topology(m);
  EXPECT_EQ(topology.neighbour(0, 3), 1);  // face opposite node 3 is (0, 1, 2)
  EXPECT_EQ(topology.boundaryFaces().size(), 6u);
  EXPECT_TRUE(topology.touchesBoundary(0));
  for (const BoundaryFace& f : topology.boundaryFaces()) {
    const auto n = faceNodes(m.tets[f.tet], f.face);
    const Vec3 normal = (m.nodes[n[1]] - m.nodes[n[0]]).cross(m.nodes[n[2]] - m.nodes[n[0]]);
    const Vec3 opposite = m.nodes[m.tets[f.tet][f.face]];
    EXPECT_LT(normal.dot(opposite - m.nodes[n[0]]), 0) << "outward: away from the tet's own opposite node";
  }
}

TEST(TetTopologyTest, InspectionReportsInvertedDegenerateUnusedAndNonManifold) {
  TetMesh m = twoTets();
  m.nodes.push_back(Vec3(5, 5, 5));       // node 5: unused
  std::swap(m.tets[1][0], m.tets[1][1]);  // tet 1 inverted
  m.nodes.push_back(Vec3(0.5, 0.5, 0));   // node 6 in the plane z = 0
  m.tets.push_back({0, 1, 2, 6});         // tet 2: zero volume, and a third user of face (0, 1, 2)
  const TetTopology topology(m);
  const MeshReport r = inspectMesh(m, topology);
  EXPECT_EQ(r.invertedTets, 1u);
  EXPECT_EQ(r.firstInverted, std::vector<int32_t>{1});
  EXPECT_EQ(r.degenerateTets, 1u);
  EXPECT_EQ(r.firstDegenerate, std::vector<int32_t>{2});
  EXPECT_EQ(r.unusedNodes, 1u);
  EXPECT_EQ(r.nonManifoldFaces, 1u);
  const std::string text = r.describe();
  EXPECT_NE(text.find("1 tetrahedra with negative volume (first: 1)"), std::string::npos) << text;
  EXPECT_NE(text.find("1 nodes used by no tetrahedron (first: 5)"), std::string::npos) << text;
  EXPECT_EQ(reorient(m), 1u);
  EXPECT_GT(signedVolume(m.nodes[m.tets[1][0]], m.nodes[m.tets[1][1]], m.nodes[m.tets[1][2]], m.nodes[m.tets[1][3]]),
            0.0);
}

TEST(UniformGridTest, ItemsAreListedInEveryCellTheirBoxesOverlap) {
  UniformGrid grid;
  std::vector<Box3> boxes = {Box3(Vec3(0, 0, 0), Vec3(1, 1, 1)), Box3(Vec3(2.5, 2.5, 2.5), Vec3(3.5, 3.5, 3.5))};
  grid.build(Box3(Vec3(0, 0, 0), Vec3(4, 4, 4)), 1.0, boxes);
  EXPECT_EQ(grid.dims(), (std::array<int32_t, 3>{5, 5, 5}));  // 4 mm plus a hair
  const auto first = grid.items(grid.cellOf(Vec3(0.5, 0.5, 0.5)));
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0], 0);
  EXPECT_EQ(grid.items(grid.cellOf(Vec3(3.0, 3.0, 3.0))).size(), 1u);
  EXPECT_EQ(grid.items(grid.cellOf(Vec3(1.5, 3.5, 0.5))).size(), 0u);
  EXPECT_EQ(grid.cellOf(Vec3(-0.1, 1, 1)), -1);
  EXPECT_EQ(grid.cellOf(Vec3(std::nan(""), 1, 1)), -1);
  // 8 cells for box 0 (it touches the faces at 1), 8 for box 1.
  EXPECT_EQ(grid.entryCount(), 16u);
}

}  // namespace
}  // namespace trephine::tetra
