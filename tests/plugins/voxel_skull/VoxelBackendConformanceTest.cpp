// Every collision back-end of VoxelSkull answers the same queries on the same
// data against closed forms, with its own stated tolerance: a ball of bone
// (density falling linearly with the distance from its centre, so the
// isovalue is a sphere of radius R) and a spherical burr of radius r whose
// centre is D from the ball's. Penetration R + r - D (shallow, deep, and
// with the burr's centre inside the ball) along the centre's direction; no
// contact beyond touching; a head-on sweep stops where the spheres touch; a
// ray meets the sphere; a burr sunk more than a voxel overlaps visibly. The tolerances are the methods' own errors:
//  - native: the trilinear surface departs from the sphere by about
//    h^2 / 8R (0.013 mm here); the deepest point of 466 shell points lies
//    within about 0.08 rad of the contact axis (2.5 mm (1 - cos 0.08) =
//    0.008 mm); within half a voxel of the surface depths are first-order
//    in the density, (code - iso) / |gradient|, whose trilinear gradient is
//    off by a few percent here; deeper they are searched along the shell
//    points' normals (a first-order distance there is wrong in real bone,
//    where the density levels off or rises again towards a cortical table):
//    0.04 mm plus 1% of the depth (0.036 mm worst measured); the normal, a
//    depth-weighted sum of point normals, turns by 0.046 rad with the
//    centre 1 mm inside the ball;
//  - embree and bullet (the same triangles): they lie within 0.041 mm of the
//    sphere (IsoSurfaceTest), and the sphere's distance to them is exact; the
//    normal, the mean of the face normals of the triangles the burr reaches
//    weighted by depth and area (continuous across creases), turns with the
//    facets: 0.079 rad at worst with the centre 1 mm inside the ball (where
//    it is the closest point's direction).
// The figures each back-end reaches are recorded as test properties.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "framework/geometry/ShellSampling.h"
#include "plugins/voxel_skull/MeshVoxelBackend.h"
#include "plugins/voxel_skull/NativeVoxelBackend.h"
#ifdef TREPHINE_HAS_EMBREE_BACKEND
#include "plugins/embree/EmbreeEngine.h"
#endif
#ifdef TREPHINE_HAS_BULLET_BACKEND
#include "plugins/bullet/BulletEngine.h"
#endif

namespace trephine::voxel {
namespace {

constexpr double kBall = 9.3;  // mm, R
constexpr double kBurr = 2.5;  // mm, r
constexpr int kSide = 40;      // voxels of 1 mm

struct Backend {
  std::string name;
  std::function<std::unique_ptr<VoxelBackend>()> create;
  double penetration;  // mm, allowed error of the penetration, plus
  double perDepth;     // this fraction of the penetration
  double angle;        // rad, allowed error of the normal
  double distance;     // mm, allowed error of a sweep's stop and a ray's hit
};

std::vector<Backend> backends() {
  std::vector<Backend> list = {
      {"native", [] { return std::make_unique<NativeVoxelBackend>(); }, 0.04, 0.01, 0.06, 0.04}};
#ifdef TREPHINE_HAS_EMBREE_BACKEND
  list.push_back({"embree", [] { return std::make_unique<MeshVoxelBackend>(std::make_unique<embree::EmbreeEngine>()); }, 0.06, 0.0, 0.1, 0.06});
#endif
#ifdef TREPHINE_HAS_BULLET_BACKEND
  list.push_back({"bullet", [] { return std::make_unique<MeshVoxelBackend>(std::make_unique<bullet::BulletEngine>()); }, 0.06, 0.0, 0.1, 0.06});
#endif
  return list;
}

class VoxelBackendConformanceTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    for (const Vec3& d : evenDirections(466)) shell.push_back({kBurr * d, -d});
    bindSolid([](const Vec3& p) { return kBall - p.norm(); });
  }
  // Bone where `depth` (mm below the surface) is positive, its density rising
  // linearly with it (isovalue 1000 on the surface), in 1 mm voxels.
  void bindSolid(const std::function<double(const Vec3&)>& depth) {
    volume = DensityVolume({kSide, kSide, kSide}, Vec3::Ones(), Vec3::Constant(-0.5 * (kSide - 1)));
    for (int32_t k = 0; k < kSide; ++k)
      for (int32_t j = 0; j < kSide; ++j)
        for (int32_t i = 0; i < kSide; ++i)
          volume.setDensity(i, j, k, std::max(0.0, 1000.0 + 100.0 * depth(volume.origin() + Vec3(i, j, k))));
    grid = SolidGrid::of(volume, 1000.0, true);
    grid.buildOccupancy();
    backend = GetParam().create();
    backend->bind({&volume, &grid, false});
    backend->reserveShell(shell);
  }
  static std::vector<Vec3> directions(int count) {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> normal;
    std::vector<Vec3> out;
    for (int n = 0; n < count; ++n) out.push_back(Vec3(normal(rng), normal(rng), normal(rng)).normalized());
    return out;
  }
  DensityVolume volume;
  SolidGrid grid;
  std::unique_ptr<VoxelBackend> backend;
  std::vector<ShellPoint> shell;
};

TEST_P(VoxelBackendConformanceTest, ContactOfASphereWithABallFollowsTheClosedForm) {
  const Backend& b = GetParam();
  double worstDepth = 0, worstAngle = 0;  // mm, rad
  for (const Vec3& u : directions(60)) {
    for (const double D : {kBall + kBurr - 0.3, kBall + kBurr - 1.7, kBall - 1.0}) {
      const VoxelContact c = backend->collide({D * u, Quat::Identity()}, shell, false);
      ASSERT_GT(c.contact.points, 0) << b.name << ", D " << D;
      const double depth = kBall + kBurr - D;
      const double error = std::abs(c.contact.penetration - depth);
      EXPECT_LT(error, b.penetration + b.perDepth * depth) << b.name << ", D " << D;
      worstDepth = std::max(worstDepth, error);
      worstAngle = std::max(worstAngle, std::acos(std::clamp(c.contact.normal.dot(u), -1.0, 1.0)));
    }
    EXPECT_EQ(backend->collide({(kBall + kBurr + 0.1) * u, Quat::Identity()}, shell, false).contact.points, 0)
        << b.name;
  }
  RecordProperty("worst_penetration_error_mm", std::to_string(worstDepth));
  RecordProperty("worst_normal_error_rad", std::to_string(worstAngle));
  EXPECT_LT(worstAngle, b.angle) << b.name;
}

TEST_P(VoxelBackendConformanceTest, AHeadOnSweepStopsWhereTheSpheresTouchAndARayMeetsTheSphere) {
  const Backend& b = GetParam();
  double worstStop = 0, worstRay = 0;
  for (const Vec3& u : directions(30)) {
    SweepQuery q;
    q.from = (kBall + kBurr + 3.0) * u;
    q.to = (kBall + kBurr - 2.0) * u;
    q.probe = SweepProbe::Line;  // head on, the leading point is where the spheres touch
    q.leadingRadius = kBurr;
    q.shell = shell;
    const SweepResult r = backend->sweep(q);
    ASSERT_TRUE(r.blocked) << b.name;
    worstStop = std::max(worstStop, std::abs((q.from + r.freeFraction * (q.to - q.from)).norm() - (kBall + kBurr)));
    q.to = q.from + 2.0 * u;
    EXPECT_FALSE(backend->sweep(q).blocked) << b.name << ": away from the ball";
    const auto hit = backend->raycast(20.0 * u, -u, 30.0);
    ASSERT_TRUE(hit) << b.name;
    worstRay = std::max(worstRay, std::abs(hit->distance - (20.0 - kBall)));
  }
  RecordProperty("worst_sweep_stop_error_mm", std::to_string(worstStop));
  RecordProperty("worst_ray_error_mm", std::to_string(worstRay));
  EXPECT_LT(worstStop, b.distance) << b.name;
  EXPECT_LT(worstRay, b.distance) << b.name;
}

TEST_P(VoxelBackendConformanceTest, ABurrSunkMoreThanAVoxelOverlapsVisibly) {
  // The displayed proxy's overlap: visible once the burr is sunk more than
  // the one-voxel tolerance (1 mm here), or its centre is in the ball.
  for (const Vec3& u : directions(20)) {
    EXPECT_FALSE(backend->overlaps({(kBall + kBurr - 0.5) * u, Quat::Identity()}, shell)) << GetParam().name;
    EXPECT_TRUE(backend->overlaps({(kBall + kBurr - 1.5) * u, Quat::Identity()}, shell)) << GetParam().name;
    EXPECT_TRUE(backend->overlaps({(kBall - 3.0) * u, Quat::Identity()}, shell)) << GetParam().name;
  }
}

// A burr whose centre is deeper in the bone than its radius (no surface
// within its reach): still in contact, pushed out along the radius, deeper
// than its radius; and a sweep from there outwards is free (the tool may
// always leave).
TEST_P(VoxelBackendConformanceTest, ACentreDeeperThanTheRadiusIsStillInContactAndMayLeave) {
  const Backend& b = GetParam();
  for (const Vec3& u : directions(20)) {
    const Vec3 centre = (kBall - kBurr - 1.0) * u;  // 3.5 mm below the surface
    const VoxelContact c = backend->collide({centre, Quat::Identity()}, shell, false);
    ASSERT_GT(c.contact.points, 0) << b.name;
    // The mesh back-ends measure the sphere itself; the native pointshell is
    // buried whole there, its points' normals cancel and it gives no
    // direction (the proxy keeps it from ever getting so deep).
    if (b.name != "native") {
      EXPECT_GT(c.contact.normal.dot(u), std::cos(b.angle)) << b.name;
      EXPECT_NEAR(c.contact.penetration, kBurr + kBurr + 1.0, b.penetration) << b.name;
    }
    SweepQuery q;
    q.from = centre;
    q.to = centre + 2.0 * u;
    q.probe = SweepProbe::Line;
    q.leadingRadius = kBurr;
    q.shell = shell;
    EXPECT_FALSE(backend->sweep(q).blocked) << b.name << ": leaving from inside the bone";
  }
}

// A tilted plane (normal (0.3, 0.2, 0.93)): grazing (0.05 mm), shallow and
// deep contact at positions across the voxels; the penetration is r minus
// the centre's height, the normal the plane's, and a sphere 0.05 mm above it
// touches nothing.
TEST_P(VoxelBackendConformanceTest, ContactWithAPlaneFollowsTheClosedFormFromGrazingToDeep) {
  const Backend& b = GetParam();
  const Vec3 n = Vec3(0.3, 0.2, 0.93).normalized();
  bindSolid([&](const Vec3& p) { return -p.dot(n); });
  const Vec3 along = n.unitOrthogonal(), across = n.cross(along);
  double worstDepth = 0, worstAngle = 0;
  for (int k = 0; k < 25; ++k) {
    // Spread over a voxel's width in both directions along the plane.
    const Vec3 place = 0.21 * (k % 5) * along + 0.23 * (k / 5) * across;
    for (const double depth : {0.05, 0.3, 1.7}) {
      const VoxelContact c = backend->collide({place + (kBurr - depth) * n, Quat::Identity()}, shell, false);
      ASSERT_GT(c.contact.points, 0) << b.name << ", depth " << depth;
      const double error = std::abs(c.contact.penetration - depth);
      EXPECT_LT(error, b.penetration + b.perDepth * depth) << b.name << ", depth " << depth;
      worstDepth = std::max(worstDepth, error);
      worstAngle = std::max(worstAngle, std::acos(std::clamp(c.contact.normal.dot(n), -1.0, 1.0)));
    }
    EXPECT_EQ(backend->collide({place + (kBurr + 0.05) * n, Quat::Identity()}, shell, false).contact.points, 0)
        << b.name;
  }
  RecordProperty("worst_penetration_error_mm", std::to_string(worstDepth));
  RecordProperty("worst_normal_error_rad", std::to_string(worstAngle));
  EXPECT_LT(worstAngle, b.angle) << b.name;
}

// A burr on a shaft (a capsule: 2.5 mm burr, 1 mm shaft 20 mm long) lying
// almost along the tilted plane, its burr 4 mm above it and the shaft
// dipping 9.3 to 25 degrees, so that only the shaft is in the bone, its end
// 0.22 to 5.4 mm deep (shallower than the shaft's radius, the wall touches
// with its lowest generator; deeper than its diameter, the end is all in
// bone): the penetration is the depth of the shaft's lowest point,
// centre_end . n less r sqrt(1 - (d . n)^2), and the normal the plane's, on
// every back-end (each takes the tool its own way: the native one and
// Embree point by point, Bullet as a sphere and a cylinder). The shaft's
// wall is sampled in rings 0.25 mm apart of 24 points, the last at its end:
// the lowest generator is missed by at most r (1 - cos 7.5 deg), 0.009 mm.
TEST_P(VoxelBackendConformanceTest, ABurrOnAShaftTouchesWithItsShaftAsTheClosedFormSays) {
  const Backend& b = GetParam();
  const Vec3 n = Vec3(0.3, 0.2, 0.93).normalized();
  bindSolid([&](const Vec3& p) { return -p.dot(n); });
  constexpr double kShaft = 1.0, kLength = 20.0;
  std::vector<ShellPoint> capsule;
  for (const Vec3& d : evenDirections(466))
    if (!(d.z() > 0 && (kBurr * d - kBurr * d.z() * Vec3::UnitZ()).norm() < kShaft)) capsule.push_back({kBurr * d, -d});
  const double wallStart = std::sqrt(kBurr * kBurr - kShaft * kShaft);
  for (int ring = 0; wallStart + 0.25 * (ring - 1) < kLength; ++ring) {
    const double z = std::min(wallStart + 0.25 * ring, kLength);
    for (int k = 0; k < 24; ++k) {
      const Vec3 radial(std::cos(k * M_PI / 12), std::sin(k * M_PI / 12), 0);
      capsule.push_back({kShaft * radial + z * Vec3::UnitZ(), -radial});
    }
  }
  backend->reserveShell(capsule);
  backend->describeTool(capsule, {kBurr, kShaft, kLength, Vec3::UnitZ()});
  const Vec3 along = n.unitOrthogonal();
  double worst = 0;
  for (const double degrees : {9.3, 10.0, 10.7, 12.0, 15.0, 20.0, 25.0}) {
    const double tilt = degrees * M_PI / 180;
    const Vec3 axis = std::cos(tilt) * along - std::sin(tilt) * n;  // the shaft, dipping into the plane
    const Quat orientation = rotationBetween(Vec3::UnitZ(), axis);
    const Vec3 burr = -6.0 * along + 4.0 * n;
    const Vec3 end = burr + kLength * axis;
    const double depth = -(end.dot(n) - kShaft * std::sqrt(1 - axis.dot(n) * axis.dot(n)));
    ASSERT_GT(depth, 0.1) << degrees;
    const VoxelContact c = backend->collide({burr, orientation}, capsule, false);
    ASSERT_GT(c.contact.points, 0) << b.name << ", " << degrees << " degrees";
    const double error = std::abs(c.contact.penetration - depth);
    EXPECT_LT(error, b.penetration + b.perDepth * depth + 0.01)
        << b.name << ", " << degrees << " degrees: " << c.contact.penetration << " mm for " << depth;
    EXPECT_GT(c.contact.normal.dot(n), std::cos(b.angle)) << b.name << ", " << degrees << " degrees";
    worst = std::max(worst, error);
  }
  RecordProperty("capsule_worst_penetration_error_mm", std::to_string(worst));
}

// A tool a plugin defines, neither a sphere nor a burr on a shaft: an
// ellipsoid (semi-axes 4, 2 and 2 mm, 600 points on a stretched Fibonacci
// spiral, as the out-of-tree example's EllipsoidTool), turned three ways and
// pressed 0.2 to 1.6 mm into the tilted plane. Its lowest point along the
// normal n is sqrt(sum_i (a_i (R^T n)_i)^2) below its centre (the support of
// the ellipsoid), so the penetration is that less the centre's height, and
// the normal the plane's. The native back-end and Embree take it point by
// point; Bullet takes only spheres and shafts and refuses it when described.
TEST_P(VoxelBackendConformanceTest, APluginsOwnToolShapeTouchesAsTheClosedFormSays) {
  const Backend& b = GetParam();
  const Vec3 n = Vec3(0.3, 0.2, 0.93).normalized();
  bindSolid([&](const Vec3& p) { return -p.dot(n); });
  const Vec3 axes(4, 2, 2);
  std::vector<ShellPoint> ellipsoid;
  const int count = 600;
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1 - 2 * (i + 0.5) / count, r = std::sqrt(1 - z * z);
    const Vec3 p = Vec3(r * std::cos(golden * i), r * std::sin(golden * i), z).cwiseProduct(axes);
    ellipsoid.push_back({p, -p.cwiseQuotient(axes.cwiseProduct(axes)).normalized()});
  }
  backend->reserveShell(ellipsoid);
  if (b.name == "bullet") {
    EXPECT_THROW(backend->describeTool(ellipsoid, {0, 0, 0, Vec3::UnitZ()}), std::runtime_error);
    return;
  }
  backend->describeTool(ellipsoid, {0, 0, 0, Vec3::UnitZ()});
  double worst = 0;
  for (const Quat& turn : {Quat::Identity(), Quat(Eigen::AngleAxisd(0.6, Vec3(1, 2, 0.5).normalized())),
                           Quat(Eigen::AngleAxisd(1.3, Vec3(-0.4, 0.3, 1).normalized()))})
    for (const double depth : {0.2, 0.8, 1.6}) {
      const Vec3 local = turn.conjugate() * n;
      const double support = axes.cwiseProduct(local).norm();
      const Vec3 centre = Vec3(1.3, -0.7, 0) - (Vec3(1.3, -0.7, 0).dot(n)) * n + (support - depth) * n;
      const VoxelContact c = backend->collide({centre, turn}, ellipsoid, false);
      ASSERT_GT(c.contact.points, 0) << b.name << ", depth " << depth;
      const double error = std::abs(c.contact.penetration - depth);
      EXPECT_LT(error, b.penetration + b.perDepth * depth + 0.02) << b.name << ", depth " << depth << ": "
                                                                  << c.contact.penetration;
      EXPECT_GT(c.contact.normal.dot(n), std::cos(b.angle)) << b.name << ", depth " << depth;
      worst = std::max(worst, error);
      // Lifted 0.05 mm clear: no contact.
      EXPECT_EQ(backend->collide({centre + (depth + 0.05) * n, turn}, ellipsoid, false).contact.points, 0) << b.name;
    }
  RecordProperty("ellipsoid_worst_penetration_error_mm", std::to_string(worst));
}

// A plate 2 mm thick (thinner than the burr's radius) seen from both sides:
// pressed 0.3 mm into its top or its bottom, the normal points out of the
// side the burr is on and the penetration is that of the face it presses.
TEST_P(VoxelBackendConformanceTest, AThinPlateIsTouchedFromTheSideTheBurrIsOn) {
  const Backend& b = GetParam();
  constexpr double kHalfThickness = 1.0;  // mm
  bindSolid([](const Vec3& p) { return kHalfThickness - std::abs(p.z()); });
  for (const double side : {1.0, -1.0})
    for (const double x : {0.0, 0.37, 0.5}) {
      const Vec3 centre(x, 0.25, side * (kHalfThickness + kBurr - 0.3));
      const VoxelContact c = backend->collide({centre, Quat::Identity()}, shell, false);
      ASSERT_GT(c.contact.points, 0) << b.name;
      EXPECT_NEAR(c.contact.penetration, 0.3, b.penetration + b.perDepth * 0.3) << b.name << " side " << side;
      EXPECT_GT(c.contact.normal.z() * side, std::cos(b.angle)) << b.name << " side " << side;
    }
}

// The mesh back-ends' hard spots: the burr's closest point exactly on a
// vertex of the isosurface (the plane z = 0.3 crosses the cells' vertical
// edges there, at voxel-centre x and y) or on an edge between two of them;
// every back-end gives the flat answer there.
TEST_P(VoxelBackendConformanceTest, OnAMeshVertexOrEdgeTheContactIsTheFlatOne) {
  const Backend& b = GetParam();
  bindSolid([](const Vec3& p) { return 0.3 - p.z(); });
  const Vec3 vertex = volume.origin() + Vec3(20, 20, 0);  // a voxel centre's x and y
  for (const Vec3& offset : {Vec3(0, 0, 0), Vec3(0.5, 0, 0), Vec3(0, 0.5, 0), Vec3(0.5, 0.5, 0)}) {
    const Vec3 centre(vertex.x() + offset.x(), vertex.y() + offset.y(), 0.3 + kBurr - 0.2);
    const VoxelContact c = backend->collide({centre, Quat::Identity()}, shell, false);
    ASSERT_GT(c.contact.points, 0) << b.name;
    ASSERT_TRUE(c.contact.normal.allFinite() && std::isfinite(c.contact.penetration)) << b.name;
    EXPECT_NEAR(c.contact.penetration, 0.2, b.penetration + b.perDepth * 0.2) << b.name << " at " << offset.transpose();
    EXPECT_GT(c.contact.normal.z(), std::cos(b.angle)) << b.name << " at " << offset.transpose();
  }
}

// A groove: bone below z = |x| / 2 (two planes meeting in a concave crease
// along y). The burr slides across it resting on both walls; the closest
// point of the surface jumps from one wall to the other at x = 0 (the
// normals of the walls are 53 deg apart), but a contact normal that jumps
// makes a proxy lifted along it chatter: every back-end turns its normal
// gradually, by less than 0.05 rad between poses 0.02 mm apart, and it
// stays within the walls' normals.
TEST_P(VoxelBackendConformanceTest, TheNormalTurnsGraduallyAcrossACrease) {
  const Backend& b = GetParam();
  const double slope = 0.5, norm = std::sqrt(1 + slope * slope);
  bindSolid([&](const Vec3& p) { return (slope * std::abs(p.x()) - p.z()) / norm; });
  const double height = (kBurr - 0.3) * norm;  // 0.3 mm into both walls at x = 0
  double largestTurn = 0;
  Vec3 previous = Vec3::Zero();
  for (double x = -1.5; x <= 1.5 + 1e-9; x += 0.02) {
    const VoxelContact c = backend->collide({Vec3(x, 0.3, height), Quat::Identity()}, shell, false);
    ASSERT_GT(c.contact.points, 0) << b.name << " at x " << x;
    const Vec3 n = c.contact.normal;
    // Between the walls' normals (-slope, 0, 1) and (slope, 0, 1), upwards.
    EXPECT_LT(std::abs(n.y()), 0.05) << b.name << " at x " << x;
    EXPECT_GT(n.z(), 1 / norm - 0.02) << b.name << " at x " << x;
    if (previous.norm() > 0) largestTurn = std::max(largestTurn, std::acos(std::clamp(n.dot(previous), -1.0, 1.0)));
    previous = n;
  }
  RecordProperty("largest_normal_turn_rad", std::to_string(largestTurn));
  EXPECT_LT(largestTurn, 0.05) << b.name;
}

INSTANTIATE_TEST_SUITE_P(Backends, VoxelBackendConformanceTest, ::testing::ValuesIn(backends()),
                         [](const ::testing::TestParamInfo<Backend>& info) { return info.param.name; });

}  // namespace
}  // namespace trephine::voxel
