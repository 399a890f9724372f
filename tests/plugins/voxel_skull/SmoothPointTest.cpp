// The fast smooth point tests (ShellPointClassifier.cpp: occupancy cells, AVX2
// gathers) against the one-point-at-a-time reference (SolidGrid::codeAt and
// voxelOf per point): the same solid flags and voxel indices for every point,
// on the skull phantom at random placements and orientations, on voxel faces
// and centres, across and beyond the grid's faces, for NaN and infinite poses,
// on volumes whose codes sit at the isovalue, and after drilling reported
// through SolidGrid::noteLowered.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "framework/geometry/ShellSampling.h"
#include "plugins/voxel_skull/Phantoms.h"
#include "plugins/voxel_skull/ShellPointClassifier.h"

namespace trephine::voxel {
namespace {

struct Variant {
  const char* name;
  ShellPointTestFunction test;
  bool occupancy;
};

std::vector<Variant> fastVariants() {
  std::vector<Variant> variants = {{"sse2", &testShellPointsSmoothBaseline, false},
                                   {"sse2+cells", &testShellPointsSmoothBaseline, true}};
#ifdef TREPHINE_HAS_AVX2_PATH
  if (__builtin_cpu_supports("avx2")) {
    variants.push_back({"avx2", &testShellPointsSmoothAvx2, false});
    variants.push_back({"avx2+cells", &testShellPointsSmoothAvx2, true});
  }
#endif
  return variants;
}

std::vector<ShellPoint> burrShell(int count, double radius) {
  std::vector<ShellPoint> shell;
  for (const Vec3& d : evenDirections(count)) shell.push_back({radius * d, -d});
  return shell;
}

// Runs the reference and every fast variant on `shell` at each pose; counts
// the points compared and, of them, the solid ones.
class Comparison {
 public:
  Comparison(SolidGrid grid) : m_plain(grid), m_cells(grid) {
    m_plain.occupancy = nullptr;
    if (!m_cells.occupancy) m_cells.buildOccupancy();
  }
  SolidGrid& cells() { return m_cells; }

  void check(const std::vector<ShellPoint>& shell, const std::vector<Pose>& poses, const std::string& what) {
    ShellArrays arrays;
    arrays.assign(shell);
    const size_t n = shell.size();
    std::vector<int64_t> voxelRef(n), voxel(n);
    std::vector<uint8_t> solidRef(n), solid(n);
    for (size_t p = 0; p < poses.size(); ++p) {
      testShellPointsSmoothScalar(m_plain, arrays, poses[p], {voxelRef.data(), solidRef.data()});
      for (const Variant& v : fastVariants()) {
        std::fill(voxel.begin(), voxel.end(), -7);
        std::fill(solid.begin(), solid.end(), 7);
        v.test(v.occupancy ? m_cells : m_plain, arrays, poses[p], {voxel.data(), solid.data()});
        for (size_t i = 0; i < n; ++i) {
          if (voxel[i] != voxelRef[i] || solid[i] != solidRef[i]) {
            ADD_FAILURE() << what << ", " << v.name << ", pose " << p << " (" << poses[p].position.transpose()
                          << "), point " << i << ": voxel " << voxel[i] << " solid " << int(solid[i])
                          << ", reference voxel " << voxelRef[i] << " solid " << int(solidRef[i]);
            return;
          }
        }
      }
      // SolidGrid::solidAt, which the sweeps and the drilling sample, decides
      // from the same cells: it must agree with the interpolation too.
      const Eigen::Matrix3d R = poses[p].orientation.toRotationMatrix();
      for (size_t i = 0; i < n; ++i) {
        const Vec3 point = R * shell[i].position + poses[p].position;
        const bool reference = m_plain.codeAt(point) > m_plain.isoCode;
        if (m_cells.solidAt(point) != reference || m_plain.solidAt(point) != reference) {
          ADD_FAILURE() << what << ", solidAt, pose " << p << ", point " << i << " (" << point.transpose()
                        << "): cells " << m_cells.solidAt(point) << ", plain " << m_plain.solidAt(point)
                        << ", interpolation " << reference;
          return;
        }
      }
      compared += n;
      for (size_t i = 0; i < n; ++i) solidPoints += solidRef[i];
    }
  }
  size_t compared = 0, solidPoints = 0;

 private:
  SolidGrid m_plain, m_cells;
};

Pose randomPose(std::mt19937_64& rng, const Vec3& position) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  q.normalize();
  Pose pose;
  pose.position = position;
  pose.orientation = q;
  return pose;
}

// Burr centres on the phantom's bone: a random direction from the grid's centre,
// the smooth surface found along it, the centre placed `depth` into the bone.
std::vector<Pose> placementsOnTheBone(const SolidGrid& grid, std::mt19937_64& rng, int count) {
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> depth(-1.0, 1.5);
  const Vec3 centre = grid.corner + 0.5 * Vec3(grid.nx * grid.spacing.x(), grid.ny * grid.spacing.y(),
                                               grid.nz * grid.spacing.z());
  std::vector<Pose> poses;
  while (int(poses.size()) < count) {
    Vec3 d(normal(rng), normal(rng), normal(rng));
    if (d.norm() < 1e-6) continue;
    d.normalize();
    Vec3 p = centre + 150.0 * d;
    while ((p - centre).norm() > 1.0 && !grid.solidAt(p)) p -= 0.05 * d;
    if ((p - centre).norm() <= 1.0) continue;  // through the opening
    poses.push_back(randomPose(rng, p + (2.5 - depth(rng)) * d));
  }
  return poses;
}

SolidGrid skullGrid(DensityVolume& volume) {
  SolidGrid grid = SolidGrid::of(volume, 400.0, true);
  grid.buildOccupancy();
  return grid;
}

TEST(VoxelSmoothPointTest, BestSmoothTestIsTheFastOne) {
  // The fast tests reproduce Eigen's R * p + t; were the check to fail, the
  // reference would be chosen and this build would lose the speed silently.
  EXPECT_NE(bestShellPointTest(true), &testShellPointsSmoothScalar);
}

TEST(VoxelSmoothPointTest, RandomPlacementsOnTheSkullPhantom) {
  DensityVolume volume = makeSkullPhantom(1.0);
  Comparison comparison(skullGrid(volume));
  std::mt19937_64 rng(11);
  comparison.check(burrShell(466, 2.5), placementsOnTheBone(comparison.cells(), rng, 1500), "on the bone, 466");
  comparison.check(burrShell(2000, 2.5), placementsOnTheBone(comparison.cells(), rng, 200), "on the bone, 2000");
  comparison.check(burrShell(37, 6.0), placementsOnTheBone(comparison.cells(), rng, 500), "on the bone, 37 of 6 mm");
  // Anywhere in and around the grid.
  const SolidGrid& grid = comparison.cells();
  const Vec3 size(grid.nx * grid.spacing.x(), grid.ny * grid.spacing.y(), grid.nz * grid.spacing.z());
  std::uniform_real_distribution<double> unit(-0.05, 1.05);
  std::vector<Pose> anywhere;
  for (int k = 0; k < 2000; ++k)
    anywhere.push_back(randomPose(rng, grid.corner + Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(size)));
  comparison.check(burrShell(466, 2.5), anywhere, "anywhere");
  EXPECT_GT(comparison.compared, 2'000'000u);
  // Both answers occur often.
  EXPECT_GT(comparison.solidPoints, comparison.compared / 20);
  EXPECT_LT(comparison.solidPoints, comparison.compared / 2);
}

TEST(VoxelSmoothPointTest, TheBenchmarkCircleOnSkull5) {
  DensityVolume volume = makeSkullPhantom(0.5);
  Comparison comparison(skullGrid(volume));
  const SolidGrid& grid = comparison.cells();
  std::vector<Pose> poses;
  for (int k = 0; k < 256; ++k) {
    const double angle = 2 * 3.14159265358979 * k / 256.0;
    Vec3 p(5 * std::cos(angle), 5 * std::sin(angle), 80);
    while (p.z() > -80 && !grid.solidAt(p)) p.z() -= 0.01;
    p.z() += 2.5 - 0.3;
    Pose pose;
    pose.position = p;
    poses.push_back(pose);
  }
  comparison.check(burrShell(466, 2.5), poses, "Skull5 circle");
  EXPECT_GT(comparison.solidPoints, 0u);
}

// Shell points exactly on voxel faces, edges, corners and centres (identity
// orientation, so the world points are the grid's own coordinates), over the
// whole grid and 3 voxels beyond it, where codeAt's range ends (1.5 voxels out
// of the outer centres) and where the cells take outsideCode.
TEST(VoxelSmoothPointTest, PointsOnVoxelFacesAndCentresInAndAroundTheGrid) {
  DensityVolume volume = makeWallPhantom(1.0, 6.0, 16.0);  // 16^3 voxels, a wall across the middle
  Comparison comparison(skullGrid(volume));
  const SolidGrid& grid = comparison.cells();
  std::vector<ShellPoint> shell;
  for (int k = -6; k <= 2 * grid.nz + 6; ++k)
    for (int j = -6; j <= 2 * grid.ny + 6; ++j)
      for (int i = -6; i <= 2 * grid.nx + 6; ++i)
        shell.push_back({grid.corner + 0.5 * Vec3(i * grid.spacing.x(), j * grid.spacing.y(), k * grid.spacing.z()),
                         Vec3::UnitZ()});
  Pose identity;
  identity.position = Vec3::Zero();
  // The same points shifted by a quarter and a tenth of a voxel, and a ulp.
  Pose quarter = identity, tenth = identity, ulp = identity;
  quarter.position = Vec3(0.25, -0.25, 0.25);
  tenth.position = Vec3(-0.1, 0.1, 0.1);
  ulp.position = Vec3(1e-15, -1e-15, 2e-15);
  comparison.check(shell, {identity, quarter, tenth, ulp}, "faces and centres");
  EXPECT_GT(comparison.solidPoints, 0u);
}

// A wall touching two faces of the grid: cells on the faces mix bone and
// outsideCode, and interpolate through codeAt.
TEST(VoxelSmoothPointTest, BoneOnTheGridFaces) {
  DensityVolume volume = makeChannelPhantom(0.5, 3.0, 12.0);  // solid block to every face, a channel along z
  Comparison comparison(skullGrid(volume));
  const SolidGrid& grid = comparison.cells();
  std::mt19937_64 rng(5);
  const Vec3 size(grid.nx * grid.spacing.x(), grid.ny * grid.spacing.y(), grid.nz * grid.spacing.z());
  std::uniform_real_distribution<double> unit(-0.2, 1.2);
  std::vector<Pose> poses;
  for (int k = 0; k < 3000; ++k)
    poses.push_back(randomPose(rng, grid.corner + Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(size)));
  comparison.check(burrShell(466, 2.5), poses, "channel block");
  EXPECT_GT(comparison.solidPoints, comparison.compared / 10);
}

TEST(VoxelSmoothPointTest, NaNAndInfinitePoses) {
  DensityVolume volume = makeSkullPhantom(1.5);
  Comparison comparison(skullGrid(volume));
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  std::vector<Pose> poses;
  Pose pose;
  pose.position = Vec3(nan, 0, 60);
  poses.push_back(pose);
  pose.position = Vec3(0, 0, nan);
  poses.push_back(pose);
  pose.position = Vec3(inf, 0, 0);
  poses.push_back(pose);
  pose.position = Vec3(-inf, inf, 0);
  poses.push_back(pose);
  pose.position = Vec3(1e300, -1e300, 1e30);
  poses.push_back(pose);
  pose.position = Vec3(0, 0, 60);
  pose.orientation = Eigen::Quaterniond(nan, 0, 0, 0);
  poses.push_back(pose);
  pose.orientation = Eigen::Quaterniond(inf, 1, 0, 0);
  poses.push_back(pose);
  comparison.check(burrShell(466, 2.5), poses, "NaN and infinite poses");
  std::vector<ShellPoint> odd = burrShell(64, 2.5);
  odd[3].position = Vec3(nan, 0, 0);
  odd[40].position = Vec3(0, inf, 0);
  pose = Pose();
  pose.position = Vec3(0, 0, 60);
  comparison.check(odd, {pose}, "NaN shell points");
}

// Random codes within a few steps of an integer isovalue: points whose 8
// corners sit exactly at the isovalue, or one step off, all over the volume; a
// non-integer isovalue in code units; and a volume whose lowest density is
// above the isovalue, so that the space around the grid is bone.
TEST(VoxelSmoothPointTest, CodesAtTheIsovalue) {
  std::mt19937_64 rng(3);
  const struct {
    double scale, offset, isovalue;
    int low, high;  // codes drawn from [low, high]
  } cases[] = {{1.0, 0.0, 400.0, 398, 402}, {1.0, 0.0, 400.0, 400, 401}, {1.0, 0.0, 400.0, 399, 400},
               {0.37, 12.0, 400.0, 1045, 1051}, {1.0, 0.0, 400.0, 401, 405}, {1.0, -32768.0, -32767.5, -32768, 32767}};
  for (const auto& c : cases) {
    DensityVolume volume({13, 11, 9}, Vec3(0.5, 0.7, 0.3), Vec3(-2, 1, 0.25), DensityEncoding{c.offset, c.scale});
    std::uniform_int_distribution<int> code(c.low, c.high);
    for (VoxelCode& v : volume.codeVector()) v = VoxelCode(code(rng));
    Comparison comparison(skullGrid(volume));
    const SolidGrid& grid = comparison.cells();
    const Vec3 size(grid.nx * grid.spacing.x(), grid.ny * grid.spacing.y(), grid.nz * grid.spacing.z());
    std::uniform_real_distribution<double> unit(-0.3, 1.3);
    std::vector<Pose> poses;
    for (int k = 0; k < 400; ++k)
      poses.push_back(randomPose(rng, grid.corner + Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(size)));
    comparison.check(burrShell(200, 1.0), poses,
                     "codes " + std::to_string(c.low) + ".." + std::to_string(c.high) + " scale " +
                         std::to_string(c.scale));
  }
}

// Every cell state against its 8 corners (codeAtCell, outsideCode beyond the
// grid): "inside" only with every corner above the isovalue, "outside" only
// with none.
void expectCellsAgreeWithCorners(const SolidGrid& grid) {
  const OccupancyCells& cells = *grid.occupancy;
  size_t decided = 0;
  for (int64_t k = -2; k <= grid.nz; ++k)
    for (int64_t j = -2; j <= grid.ny; ++j)
      for (int64_t i = -2; i <= grid.nx; ++i) {
        double low = std::numeric_limits<double>::infinity(), high = -low;
        for (int c = 0; c < 8; ++c) {
          const double v = grid.codeAtCell(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2));
          low = std::min(low, v), high = std::max(high, v);
        }
        const uint8_t state = cells.state(cells.cellIndex(i, j, k));
        if (state == OccupancyCells::kInside) {
          ASSERT_GT(low, grid.isoCode) << i << " " << j << " " << k;
        } else if (state == OccupancyCells::kOutside) {
          ASSERT_LT(high, grid.isoCode) << i << " " << j << " " << k;
        }
        decided += state != OccupancyCells::kSurface;
      }
  EXPECT_GT(decided, 0u);
}

// Drilling lowers codes; noteLowered keeps the cells exact. Voxels around
// random points near the bone lose random amounts (some to the floor, some
// staying above the isovalue), then the tests compare again.
TEST(VoxelSmoothPointTest, DrillingReportedThroughNoteLowered) {
  DensityVolume volume = makeSkullPhantom(1.5);
  SolidGrid grid = skullGrid(volume);
  expectCellsAgreeWithCorners(grid);
  Comparison comparison(grid);  // shares the codes and the cells with `grid`
  std::mt19937_64 rng(17);
  const std::vector<Pose> cuts = placementsOnTheBone(grid, rng, 300);
  std::uniform_int_distribution<int> amount(0, 1600);
  std::uniform_int_distribution<int> offset(-3, 3);
  for (const Pose& cut : cuts) {
    const Vec3 u = (cut.position - grid.corner).cwiseProduct(grid.inverseSpacing);
    for (int n = 0; n < 60; ++n) {
      const int64_t i = int64_t(u.x()) + offset(rng), j = int64_t(u.y()) + offset(rng), k = int64_t(u.z()) + offset(rng);
      if (!grid.inside(i, j, k)) continue;
      const int64_t v = grid.linear(i, j, k);
      const VoxelCode lowered = VoxelCode(std::max(0, int(grid.codes[v]) - amount(rng)));
      grid.codes[v] = lowered;
      grid.noteLowered(v, lowered);
    }
  }
  expectCellsAgreeWithCorners(grid);
  comparison.check(burrShell(466, 2.5), cuts, "drilled, at the cuts");
  comparison.check(burrShell(466, 2.5), placementsOnTheBone(grid, rng, 1000), "drilled, on the bone");
  // Out-of-range indices are ignored.
  grid.noteLowered(-1, 0);
  grid.noteLowered(int64_t(grid.nx) * grid.ny * grid.nz, 0);
  // Without occupancy cells the hook does nothing.
  SolidGrid plain = SolidGrid::of(volume, 400.0, true);
  plain.noteLowered(0, 0);
  EXPECT_EQ(plain.occupancy, nullptr);
  // Voxel surface: no cells are built.
  SolidGrid voxels = SolidGrid::of(volume, 400.0, false);
  voxels.buildOccupancy();
  EXPECT_EQ(voxels.occupancy, nullptr);
}

}  // namespace
}  // namespace trephine::voxel
