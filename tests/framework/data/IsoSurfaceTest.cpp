// The skull's surface as triangles (IsoSurface.cpp, marching tetrahedra on
// the trilinear density): on a ball whose density falls linearly with the
// distance from its centre, the vertices lie on the sphere and the surface is
// closed, faces out and holds the ball's volume (closed forms); a drilled
// region re-extracted block by block, across a block's faces, equals a fresh
// extraction; an isovalue equal to voxel codes gives no zero-area triangle.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "framework/data/IsoSurface.h"
#include "plugins/voxel_skull/SolidGrid.h"

namespace trephine::voxel {
namespace {

constexpr double kRadius = 9.3;  // mm
constexpr int kSide = 40;        // voxels of 1 mm, the ball in the middle

// Density 1000 + 100 (R - distance), so the isovalue 1000 is the sphere of radius R.
DensityVolume ball(double voxel = 1.0, int side = kSide) {
  const Vec3 origin = Vec3::Constant(-0.5 * (side - 1) * voxel);
  DensityVolume volume({side, side, side}, Vec3::Constant(voxel), origin);
  for (int32_t k = 0; k < side; ++k)
    for (int32_t j = 0; j < side; ++j)
      for (int32_t i = 0; i < side; ++i) {
        const Vec3 p = origin + voxel * Vec3(i, j, k);
        volume.setDensity(i, j, k, std::max(0.0, 1000.0 + 100.0 * (kRadius - p.norm())));
      }
  return volume;
}

// Welds vertices at identical coordinates (block faces repeat them) and maps
// each directed edge to how often it is used.
std::map<std::pair<int, int>, int> directedEdges(const TriangleMesh& mesh) {
  std::map<std::array<double, 3>, int> ids;
  std::vector<int> weld(mesh.vertices.size());
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Vec3& p = mesh.vertices[v];
    weld[v] = ids.try_emplace({p.x(), p.y(), p.z()}, int(ids.size())).first->second;
  }
  std::map<std::pair<int, int>, int> edges;
  for (const auto& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) ++edges[{weld[size_t(t[e])], weld[size_t(t[(e + 1) % 3])]}];
  return edges;
}

// The ball's volume, its grid at the isovalue 1000 and the surface extracted from it.
struct Extracted {
  Extracted() : volume(ball()), grid(SolidGrid::of(volume, 1000.0, true)) {
    grid.buildOccupancy();
    surface.build(grid, grid.cellsWithoutSurface());
  }
  DensityVolume volume;
  SolidGrid grid;
  BlockedIsoSurface surface;
};

TEST(IsoSurfaceTest, ABallGivesAClosedOutwardSurfaceOnItsSphere) {
  Extracted ball;
  const BlockedIsoSurface& surface = ball.surface;
  const TriangleMesh mesh = surface.merged();
  ASSERT_GT(mesh.triangles.size(), 1000u);
  EXPECT_GT(surface.blockCount(), 8u) << "the ball spans several blocks";

  // On the sphere: vertices on cell edges are exact for the trilinear
  // density, whose own surface departs from the sphere by the interpolation
  // of |x| over a voxel (about h^2 / 8R, 0.013 mm here); those on the
  // tetrahedra's diagonals by up to about 3 times that.
  double worst = 0;
  for (const Vec3& p : mesh.vertices) worst = std::max(worst, std::abs(p.norm() - kRadius));
  RecordProperty("worst_vertex_off_sphere_mm", std::to_string(worst));
  EXPECT_LT(worst, 0.06);

  // Closed and consistently oriented: each directed edge once, and its reverse once.
  const auto edges = directedEdges(mesh);
  for (const auto& [edge, uses] : edges) {
    ASSERT_EQ(uses, 1) << "edge " << edge.first << "-" << edge.second;
    ASSERT_EQ(edges.count({edge.second, edge.first}), 1u)
        << "edge " << edge.first << "-" << edge.second << " is a border";
  }
  // Facing out: the enclosed volume (divergence theorem) is positive and the ball's.
  double volume6 = 0;
  for (const auto& t : mesh.triangles)
    volume6 += mesh.vertices[size_t(t[0])].dot(mesh.vertices[size_t(t[1])].cross(mesh.vertices[size_t(t[2])]));
  const double enclosed = volume6 / 6.0, exact = 4.0 / 3.0 * std::numbers::pi * std::pow(kRadius, 3);
  RecordProperty("enclosed_over_exact_volume", std::to_string(enclosed / exact));
  EXPECT_NEAR(enclosed / exact, 1.0, 0.01);
}

TEST(IsoSurfaceTest, ADrilledRegionReExtractedAcrossBlockFacesEqualsAFreshExtraction) {
  Extracted ball;
  SolidGrid& grid = ball.grid;
  BlockedIsoSurface& surface = ball.surface;
  // A pit 6 voxels wide around voxel 16 (cells of base 15 and 16 are in two
  // blocks: 16 cells from -1), into the ball's side along x.
  const std::array<int64_t, 3> first{2, 13, 13}, last{12, 18, 18};
  for (int64_t k = first[2]; k <= last[2]; ++k)
    for (int64_t j = first[1]; j <= last[1]; ++j)
      for (int64_t i = first[0]; i <= last[0]; ++i) {
        const int64_t v = grid.linear(i, j, k);
        const VoxelCode before = grid.codes[v];
        grid.codes[v] = VoxelCode(std::min<int>(before, 0));
        grid.noteLowered(v, grid.codes[v], before);
      }
  const std::vector<size_t> changed = surface.update(grid, first, last, grid.cellsWithoutSurface());
  EXPECT_GE(changed.size(), 2u) << "the pit spans a block face";
  // Extracted afresh without the occupancy cells' skip: the skip, kept up to
  // date by the drilling's hooks, leaves out no cell with a surface.
  BlockedIsoSurface fresh;
  fresh.build(grid);
  ASSERT_EQ(fresh.blockCount(), surface.blockCount());
  for (size_t b = 0; b < fresh.blockCount(); ++b) {
    EXPECT_EQ(surface.block(b).vertices, fresh.block(b).vertices) << "block " << b;
    EXPECT_EQ(surface.block(b).triangles, fresh.block(b).triangles) << "block " << b;
  }
  // And the drilled surface is still closed.
  for (const auto& [edge, uses] : directedEdges(surface.merged())) ASSERT_EQ(uses, 1);
}

TEST(IsoSurfaceTest, AnIsovalueOnTheCodesGivesNoZeroAreaTriangle) {
  // Codes 0, 1000 and 2000 with the isovalue exactly 1000: surface vertices
  // fall on voxel centres, and tetrahedra around them would give triangles
  // of no area.
  DensityVolume volume({12, 12, 12}, Vec3::Ones(), Vec3::Zero());
  for (int32_t k = 0; k < 12; ++k)
    for (int32_t j = 0; j < 12; ++j)
      for (int32_t i = 0; i < 12; ++i) {
        const bool core = i >= 3 && i <= 8 && j >= 3 && j <= 8 && k >= 3 && k <= 8;
        const bool shell = i >= 2 && i <= 9 && j >= 2 && j <= 9 && k >= 2 && k <= 9;
        volume.setDensity(i, j, k, core ? 2000.0 : shell ? 1000.0 : 0.0);
      }
  SolidGrid grid = SolidGrid::of(volume, 1000.0, true);
  grid.buildOccupancy();
  BlockedIsoSurface surface;
  surface.build(grid, grid.cellsWithoutSurface());
  const TriangleMesh mesh = surface.merged();
  ASSERT_GT(mesh.triangles.size(), 0u);
  RecordProperty("degenerate_triangles_dropped", std::to_string(surface.degenerateTriangles()));
  EXPECT_GT(surface.degenerateTriangles(), 0u) << "the case arises and is dropped";
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.vertices[size_t(t[0])];
    EXPECT_GT((mesh.vertices[size_t(t[1])] - a).cross(mesh.vertices[size_t(t[2])] - a).norm(), 0.0);
  }
}

}  // namespace
}  // namespace trephine::voxel
