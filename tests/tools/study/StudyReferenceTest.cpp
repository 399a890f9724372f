// The study's references for targets read from data, against closed forms:
// a box's tetrahedral mesh (exact distance to its faces, edges and corners,
// inside and out) and scans whose interpolated isosurface is known: a linear
// density (trilinear interpolation reproduces it, so its isosurface is the
// plane) and a ball's density sampled on a grid (converging as the voxel
// shrinks).
#include <gtest/gtest.h>

#include <random>

#include "plugins/tetra_brain/CubePhantom.h"
#include "tools/trephine/study/MeshSurfaceReference.h"
#include "tools/trephine/study/ScanIsosurface.h"

namespace trephine::study {
namespace {

constexpr double kRadius = 2.5;  // mm, the sphere

// The exact contact of a sphere of kRadius centred at p with the box |x| <= h.
ExactSphereContact boxContact(const Vec3& p, const Vec3& h) {
  const Vec3 outside = (p.cwiseAbs() - h).cwiseMax(0.0);
  ExactSphereContact c;
  if (outside.norm() > 0) {
    c.penetration = kRadius - outside.norm();
    const Vec3 nearest = p.cwiseMax(-h).cwiseMin(h);
    c.normal = (p - nearest).normalized();
    return c;
  }
  Eigen::Index axis;
  const double depth = (h - p.cwiseAbs()).minCoeff(&axis);
  c.penetration = kRadius + depth;
  c.normal = Vec3::Unit(axis) * (p[axis] >= 0 ? 1.0 : -1.0);
  return c;
}

TEST(StudyReferenceTest, ABoxMeshGivesTheBoxsExactContactEverywhereAroundAndInsideIt) {
  const Vec3 h(5, 6, 7);
  const TetMesh box = tetra::makeBoxMesh({3, 4, 5}, -h, h);
  const BoundarySurface surface = boundarySurface(box);
  EXPECT_EQ(surface.triangles.size(), 2u * 2u * (3 * 4 + 4 * 5 + 3 * 5)) << "two triangles a boundary cell face";
  for (const auto& t : surface.triangles) {
    // Turned out: the normal points away from the box's centre.
    const Vec3 &a = surface.nodes[t[0]], &b = surface.nodes[t[1]], &c = surface.nodes[t[2]];
    EXPECT_GT((b - a).cross(c - a).dot((a + b + c) / 3), 0.0);
  }
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> x(-9, 9), y(-10, 10), z(-11, 11);
  int touching = 0, inside = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(x(rng), y(rng), z(rng));
    const ExactSphereContact expected = boxContact(p, h);
    const ExactSphereContact c = meshSphereContact(surface, p, kRadius);
    EXPECT_EQ(insideSurface(surface, p), (p.cwiseAbs() - h).maxCoeff() < 0) << p.transpose();
    if (expected.penetration <= 0) {
      EXPECT_LE(c.penetration, 0.0) << p.transpose();
      continue;
    }
    ++touching;
    inside += (p.cwiseAbs() - h).maxCoeff() < 0;
    EXPECT_NEAR(c.penetration, expected.penetration, 1e-9) << p.transpose();
    // Inside, equidistant faces leave the normal's choice open: only where one face is nearest.
    Vec3 gaps = (h - p.cwiseAbs());
    std::sort(gaps.data(), gaps.data() + 3);
    if ((p.cwiseAbs() - h).maxCoeff() >= 0 || gaps[1] - gaps[0] > 1e-6)
      EXPECT_LT((c.normal - expected.normal).norm(), 1e-9) << p.transpose();
  }
  EXPECT_GT(touching, 300) << "the random points cover contact";
  EXPECT_GT(inside, 100) << "and centres inside the box";
}

// A volume of `dims` voxels of `spacing` centred on the origin, its density
// given by a function of the voxel centre.
template <typename Density>
ScanAsRead sampledScan(const std::array<int32_t, 3>& dims, double spacing, double isovalue, Density density) {
  const Vec3 origin = -0.5 * spacing * Vec3(dims[0] - 1, dims[1] - 1, dims[2] - 1);
  auto volume =
      std::make_shared<DensityVolume>(dims, Vec3::Constant(spacing), origin, DensityEncoding::fit(-3000, 3000, false));
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) volume->setDensity(i, j, k, density(volume->voxelCenter(i, j, k)));
  return {volume, isovalue};
}

TEST(StudyReferenceTest, ALinearDensitysIsosurfaceIsItsPlaneExactly) {
  // density = 400 - 100 n.p: trilinear interpolation reproduces a linear
  // field, so the isosurface at 400 is the plane n.p = 0 (bone below).
  const Vec3 n = Vec3(0.3, -0.2, 0.93).normalized();
  const ScanAsRead scan = sampledScan({24, 24, 24}, 1.0, 400, [&](const Vec3& p) { return 400 - 100 * p.dot(n); });
  const LevelSet isosurface = scanIsosurface(scan);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-4, 4);
  for (int i = 0; i < 25; ++i) {
    const double depth = 0.05 + 0.12 * i;  // mm, 0.05 to 2.93 (the centre inside beyond 2.5)
    const Vec3 centre = (kRadius - depth) * n + Vec3(u(rng), u(rng), u(rng)).cross(n);
    const ExactSphereContact c = exactSphereContact(isosurface, centre, kRadius);
    // The density is stored in 16 bits over [-3000, 3000]: its rounding (0.05
    // at most) moves the surface by at most 0.05 / 100 mm.
    EXPECT_NEAR(c.penetration, depth, 1e-3) << depth;
    EXPECT_LT((c.normal - n).norm(), 1e-3) << depth;
  }
  EXPECT_GT(isosurface(Vec3(0, 0, 100)), 0) << "outside the scan's cells is outside";
}

TEST(StudyReferenceTest, ABallsSampledDensityConvergesToTheBallAsTheVoxelsShrink) {
  // density = 1000 (8 - |p|) / 8 + 400: the isosurface at 400 is the ball of
  // radius 8; sampled and interpolated, it differs by the interpolation's
  // error, which falls with the square of the voxel.
  const double ball = 8;
  const auto errorAt = [&](double voxel) {
    const int n = int(std::ceil(24 / voxel));
    const ScanAsRead scan =
        sampledScan({n, n, n}, voxel, 400, [&](const Vec3& p) { return 1000 * (ball - p.norm()) / ball + 400; });
    const LevelSet isosurface = scanIsosurface(scan);
    double largest = 0;
    std::mt19937_64 rng(9);
    std::normal_distribution<double> g;
    for (int i = 0; i < 12; ++i) {
      const Vec3 u = Vec3(g(rng), g(rng), g(rng)).normalized();
      const ExactSphereContact c = exactSphereContact(isosurface, (ball + kRadius - 1.0) * u, kRadius);
      largest = std::max(largest, std::abs(c.penetration - 1.0));
    }
    return largest;
  };
  const double coarse = errorAt(2.0), fine = errorAt(1.0);
  EXPECT_LT(fine, 0.05);
  EXPECT_LT(fine, 0.5 * coarse) << coarse << " mm at 2 mm voxels, " << fine << " at 1 mm";
}

}  // namespace
}  // namespace trephine::study
