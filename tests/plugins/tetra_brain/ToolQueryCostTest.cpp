// The tool query's cost model (cell_size/ToolQueryCost.h): its counts against
// brute force and against the native back-end's own counts, its minimiser's
// scaling, and TetraBrain's cellSizeRule.
#include <gtest/gtest.h>

#include <array>

#include <random>

#include "plugins/tetra_brain/CubePhantom.h"
#include "plugins/tetra_brain/NativeTetBackend.h"
#include "plugins/tetra_brain/TetPhantoms.h"
#include "framework/data/TetTopology.h"
#include "plugins/tetra_brain/cell_size/ToolQueryCost.h"
#include "framework/geometry/ShellSampling.h"
#include "tests/plugins/tetra_brain/TetTestShapes.h"
#include "tests/support/TestSupport.h"

namespace trephine::tetra {
namespace {

std::vector<Vec3> positions(const std::vector<ShellPoint>& shell) {
  std::vector<Vec3> out;
  for (const ShellPoint& p : shell) out.push_back(p.position);
  return out;
}

// N(e): the expected count of tetrahedron boxes overlapping a box of extents
// e, against counting them for boxes placed at random deep inside the mesh.
TEST(ToolQueryCostTest, OverlapCountsMatchBoxesPlacedAtRandom) {
  const TetMesh mesh = makeCubeMesh(12);  // 200 mm cube, 8,640 tetrahedra
  const double margin = 1.5;
  const TetBoxMoments moments = measureBoxMoments(mesh, margin);
  // Each tetrahedron's box (tight, and grown by the margin) as plain bounds:
  // the count below is 276 million box tests, which plain comparisons keep
  // to seconds in the sanitizer builds, where the tests' code is not optimised.
  struct Bounds {
    std::array<double, 3> lo, hi;
    bool overlaps(const Bounds& q) const {
      return lo[0] <= q.hi[0] && q.lo[0] <= hi[0] && lo[1] <= q.hi[1] && q.lo[1] <= hi[1] && lo[2] <= q.hi[2] &&
             q.lo[2] <= hi[2];
    }
  };
  std::vector<Bounds> boxes, tightBoxes;
  for (const TetIndices& k : mesh.tets) {
    Box3 box;
    for (int32_t n : k) box.extend(mesh.nodes[n]);
    const Vec3 lo = box.min(), hi = box.max();
    tightBoxes.push_back({{lo.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), hi.z()}});
    boxes.push_back({{lo.x() - margin, lo.y() - margin, lo.z() - margin}, {hi.x() + margin, hi.y() + margin, hi.z() + margin}});
  }
  std::mt19937 random(3);
  // Over whole cells of the cube (6 of 200 / 12 mm): the tetrahedra's boxes
  // are the cube's cells, so a range of part cells would weigh their borders unevenly.
  std::uniform_real_distribution<double> where(-50, 50);
  for (const Vec3& e : {Vec3(0, 0, 0), Vec3(2, 2, 2), Vec3(10, 3, 0.5), Vec3(40, 40, 40)}) {
    double counted = 0, tight = 0;
    constexpr int kBoxes = 4000;
    for (int i = 0; i < kBoxes; ++i) {
      const Vec3 lo(where(random), where(random), where(random));
      const Bounds query{{lo.x(), lo.y(), lo.z()}, {lo.x() + e.x(), lo.y() + e.y(), lo.z() + e.z()}};
      for (const Bounds& b : boxes) counted += b.overlaps(query);
      for (const Bounds& b : tightBoxes) tight += b.overlaps(query);
    }
    counted /= kBoxes;
    tight /= kBoxes;
    EXPECT_NEAR(moments.overlapping(e), counted, 0.03 * counted) << e.transpose();
    EXPECT_NEAR(moments.tightOverlapping(e), tight, 0.03 * tight) << e.transpose();
  }
  EXPECT_NEAR(moments.volume, 200.0 * 200.0 * 200.0, 1e-6);
}

// Deep inside a uniform mesh every occupied cell is inside it, as the model
// assumes: its cells, listed and kept tetrahedra are the back-end's counts.
TEST(ToolQueryCostTest, PredictedWorkIsTheBackEndsCountDeepInsideAMesh) {
  // An unstructured mesh (a cube's tetrahedra have the cube's cells as boxes,
  // which a grid from the same corner cuts exactly on some of their faces).
  const TetMesh mesh = makeTetPhantom("sphere?tets=20000&radius=50");
  const TetTopology topology(mesh);
  const std::vector<ShellPoint> shell = shapes::sphereShell(2.5, 266);
  const std::vector<Vec3> points = positions(shell);
  const TetBoxMoments moments = measureBoxMoments(mesh, 0.0);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> where(-20, 20);  // tool and cells within 40 mm of the centre
  std::normal_distribution<double> gauss;
  for (const double cell : {0.7, 2.0, 5.0, 12.0}) {
    NativeTetBackend backend;
    TetQueryOptions options;
    options.cellSize = cell;
    backend.bind({&mesh, &topology, options});
    backend.reserveShell(shell);
    for (int i = 0; i < 400; ++i) {
      const Pose pose{Vec3(where(random), where(random), where(random)),
                      Quat(gauss(random), gauss(random), gauss(random), gauss(random)).normalized()};
      backend.findHits(pose, shell);
    }
    const auto& w = backend.locateWork();
    const double q = double(w.queries);
    // The grid's own side: it caps its cell count (7 million cells of 0.7 mm would be more).
    const ToolQueryWork predicted = predictToolQueryWork(moments, points, backend.currentGrids().tetGrid.cellSide(), 64);
    // Both are averages over random turns and shifts (64 and 400): a large
    // cell's count of a few cells carries about 4% sampling error.
    EXPECT_NEAR(predicted.cells, w.cells / q, 0.10 * predicted.cells) << cell;
    EXPECT_NEAR(predicted.listed, w.listed / q, 0.10 * predicted.listed) << cell;
    EXPECT_NEAR(predicted.overlapping, w.overlapping / q, 0.10 * predicted.overlapping) << cell;
    // Points already located skip the rest of their cell's boxes: the model's
    // every point against every kept box is an upper bound deep inside (at a
    // surface, most points find no tetrahedron and test every box).
    EXPECT_LE(w.pointTests / q, 1.02 * predicted.pointTests) << cell;
  }
}

// Every count is a ratio of lengths: a mesh and tool both s times larger
// want a cell s times larger.
TEST(ToolQueryCostTest, TheOptimalCellScalesWithTheMeshAndTheTool) {
  TetMesh mesh = makeCubeMesh(10);
  const std::vector<Vec3> shell = positions(shapes::sphereShell(2.5, 266));
  const double edge = 20.0;
  const double cell = optimalToolCellSize(measureBoxMoments(mesh, 0.0), std::vector<std::vector<Vec3>>{shell}, edge,
                                          kDeformingToolQueryWeights);
  for (Vec3& p : mesh.nodes) p *= 3.0;
  std::vector<Vec3> larger = shell;
  for (Vec3& p : larger) p *= 3.0;
  const double scaled = optimalToolCellSize(measureBoxMoments(mesh, 0.0), std::vector<std::vector<Vec3>>{larger}, 3 * edge,
                                            kDeformingToolQueryWeights);
  EXPECT_NEAR(scaled, 3 * cell, 0.03 * 3 * cell);
  // It is a minimum: the cost there is below that of half and twice the cell.
  const TetBoxMoments moments = measureBoxMoments(makeCubeMesh(10), 0.0);
  auto cost = [&](double delta) {
    return toolQueryCost(predictToolQueryWork(moments, shell, delta), kDeformingToolQueryWeights);
  };
  EXPECT_LT(cost(cell), cost(0.5 * cell));
  EXPECT_LT(cost(cell), cost(2 * cell));
}

// One point has one cell whatever its size, and a larger cell only lists
// more tetrahedra: the smallest cell searched wins (where listing costs, as on
// a deforming mesh).
TEST(ToolQueryCostTest, ASinglePointWantsTheSmallestCell) {
  const TetBoxMoments moments = measureBoxMoments(makeCubeMesh(10), 0.0);
  const std::vector<Vec3> point{Vec3::Zero()};
  EXPECT_NEAR(optimalToolCellSize(moments, std::vector<std::vector<Vec3>>{point}, 20.0, kDeformingToolQueryWeights),
              kSmallestCellInEdges * 20.0, 1e-3);
  const ToolQueryWork work = predictToolQueryWork(moments, point, 5.0);
  EXPECT_DOUBLE_EQ(work.cells, 1.0);
  EXPECT_NEAR(work.listed, moments.overlapping(Vec3::Constant(5.0)), 1e-12);
  EXPECT_NEAR(work.pointTests, moments.overlapping(Vec3::Zero()), 1e-12);
}

// TetraBrain: unset, the cell is the model's for the shells its tools
// reserve; the other rules and an explicit cell are taken as given.
TEST(ToolQueryCostTest, TetraBrainPicksItsCellByTheRule) {
  auto cellOf = [&](const std::string& fields) {
    Diagnostics d;
    auto simulation = test::loadScene(R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  <TetraBrain name="brain" file="phantom:cube?cells=10" )" + fields + R"(/>
  <ScriptedDevice name="device" path="pokes" target="@brain" direction="0 0 -1" center="0 0 0" tipOffset="2.5"/>
  <PointshellTool name="probe" radius="2.5" angleStep="15" device="@device"/>
  <GodObjectProxy name="proxy" tool="@probe" target="@brain"/>
  <ContactWarning name="warning" proxy="@proxy" target="@brain"/>
</Node>)",
                                      d);
    EXPECT_TRUE(simulation) << test::messages(d);
    if (!simulation) return 0.0;
    // The boundary faces' grid stays at half an edge or more: a deep point's
    // nearest-face search visits (depth / cell)^3 of its cells.
    EXPECT_GE(test::componentCounter(*simulation, "TetraBrain", "face_cell_size_mm"),
              std::max(test::componentCounter(*simulation, "TetraBrain", "cell_size_mm"),
                       0.5 * test::componentCounter(*simulation, "TetraBrain", "average_edge_mm")) - 1e-9);
    return test::componentCounter(*simulation, "TetraBrain", "cell_size_mm");
  };
  const TetMesh mesh = makeCubeMesh(10);
  TetraBrain brain;
  brain.setMesh(mesh);
  const double edge = shapes::native(brain).averageEdge();
  EXPECT_DOUBLE_EQ(shapes::native(brain).cellSize(), 0.5 * edge);  // until a tool reserves its shell
  // The probe's shell: the angle-step points of a 2.5 mm sphere. The proxy
  // and the warning reserve it both; it counts once.
  std::vector<Vec3> shell;
  for (const Vec3& d : angleStepDirections(15)) shell.push_back(2.5 * d);
  const double model = optimalToolCellSize(measureBoxMoments(mesh, 0.0), std::vector<std::vector<Vec3>>{shell}, edge,
                                          kRigidToolQueryWeights);
  const double tool = cellOf("");
  EXPECT_NEAR(tool, model, 1e-9 * model);
  EXPECT_LT(tool, 0.4 * edge);  // a few-millimetre tool against 20 mm tetrahedra: well below half an edge
  EXPECT_NEAR(cellOf(R"(cellSizeRule="half-edge")"), 0.5 * edge, 1e-9);
  EXPECT_NEAR(cellOf(R"(cellSizeRule="edge")"), edge, 1e-9);
  EXPECT_NEAR(cellOf(R"(cellSize="7")"), 7.0, 1e-9);
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <TetraBrain name="brain" file="phantom:cube?cells=10" cellSize="7" cellSizeRule="edge"/>
</Node>)",
                               d));
  EXPECT_NE(test::messages(d).find("inline.xml:3:"), std::string::npos) << test::messages(d);
  EXPECT_NE(test::messages(d).find("has no effect when cellSize is given"), std::string::npos) << test::messages(d);
}

}  // namespace
}  // namespace trephine::tetra
