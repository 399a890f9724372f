// The brain phantom's shape; CgalMesher.cpp meshes it (ImplicitMesher.h).
#include "plugins/tetra_brain/BrainPhantom.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "framework/meshing/TetMeshing.h"

namespace trephine::tetra {

namespace {

// Hemispheres: two ellipsoids centred at (+-kHemisphereOffset, 0, kHemisphereCentreZ)
// with semi-axes kHemisphereAxes (mm). They overlap (offset < x semi-axis), so
// the brain is one body; the top of each lies at z = 55.5 mm, and the gyri add
// up to 3 mm, which gives about 140 x 170 x 115 mm with the base at -57.5 mm.
constexpr double kHemisphereOffset = 22.0;
constexpr std::array<double, 3> kHemisphereAxes = {46.0, 83.0, 64.0};
constexpr double kHemisphereCentreZ = -8.5;
// Blend radii of the smooth unions and intersections (mm): wide enough that the
// surface has no crease that Mesh_3 would have to resolve.
constexpr double kHemisphereBlend = 10.0;
constexpr double kBaseBlend = 4.0;
constexpr double kFissureBlend = 2.0;
// Gyri: three plane waves of this wavelength (mm), each a third of the amplitude.
constexpr double kGyriWavelength = 28.0;

// The phantom's mesher settings: a bounding sphere of 110 mm (the farthest
// point is about 88 mm from the origin); the refined count of Mesh_3 with
// these criteria is about 6.0e6 / s^3 (volume) + 2.8e5 / s^2 (surface) for a
// size s from 5 to 14 mm; a facet distance of at least 0.5 mm resolves the gyri.
constexpr double kBoundingRadius = 110.0;
constexpr double kVolumeTerm = 6.0e6, kSurfaceTerm = 2.8e5;
constexpr double kLeastFacetDistance = 0.5;

// Polynomial smooth minimum: min(a, b) with the corner rounded over a width of
// k (mm); C1, and exact where |a - b| >= k.
double smoothMin(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - 0.25 * h * h * k;
}
double smoothMax(double a, double b, double k) { return -smoothMin(-a, -b, k); }

// Approximate signed distance to an ellipsoid (mm): k0 (k0 - 1) / k1 with k0 =
// |q / axes| and k1 = |q / axes^2|, zero on the surface, with unit gradient
// there and within a few percent of the distance near it.
double ellipsoidDistance(const Vec3& q, const Vec3& axes) {
  const double k0 = q.cwiseQuotient(axes).norm();
  const double k1 = q.cwiseQuotient(axes.cwiseProduct(axes)).norm();
  if (k1 < 1e-12) return -axes.minCoeff();
  return k0 * (k0 - 1.0) / k1;
}

// Outward displacement of the surface by the gyri (mm), in [-A, A].
double gyri(const Vec3& p) {
  static const std::array<Vec3, 3> directions = {Vec3(0.8, 0.6, 0.0).normalized(), Vec3(-0.3, 0.8, 0.52).normalized(),
                                                 Vec3(0.5, -0.2, 0.84).normalized()};
  constexpr std::array<double, 3> phases = {0.3, 1.7, 4.1};   // rad
  const double k = 2.0 * std::numbers::pi / kGyriWavelength;  // rad/mm
  double sum = 0.0;
  for (int i = 0; i < 3; ++i) sum += std::sin(k * directions[i].dot(p) + phases[i]);
  return kBrainGyriAmplitude * sum / 3.0;
}

// Distance from p to the fissure's midplane blade {x = 0, z >= bottom + w/2}
// minus half the width: negative inside the groove, whose bottom is a half
// cylinder reaching down to kBrainFissureBottomZ.
double fissureDistance(const Vec3& p) {
  const double bladeBottom = kBrainFissureBottomZ + 0.5 * kBrainFissureWidth;
  const double below = std::min(p.z() - bladeBottom, 0.0);
  return std::hypot(p.x(), below) - 0.5 * kBrainFissureWidth;
}

}  // namespace

double brainPhantomDistance(const Vec3& p) {
  const Vec3 axes(kHemisphereAxes[0], kHemisphereAxes[1], kHemisphereAxes[2]);
  const Vec3 left(-kHemisphereOffset, 0.0, kHemisphereCentreZ), right(kHemisphereOffset, 0.0, kHemisphereCentreZ);
  double d = smoothMin(ellipsoidDistance(p - left, axes), ellipsoidDistance(p - right, axes), kHemisphereBlend);
  d -= gyri(p);
  d = smoothMax(d, kBrainBaseZ - p.z(), kBaseBlend);
  return smoothMax(d, -fissureDistance(p), kFissureBlend);
}

TetMesh makeBrainPhantom(int targetTets) { return makeBrainPhantom(targetTets, {}); }

int32_t brainPhantomRegion(const Vec3& p, const BrainPhantomRegions& regions) {
  if (regions.vesselRadius > 0) {
    if (std::hypot(p.x() - regions.vesselAxisX(), p.z() - regions.vesselZ) < regions.vesselRadius) return kVesselLabel;
  }
  if (regions.tumourRadius > 0 && (p - regions.tumourCentre).norm() < regions.tumourRadius) return kTumourLabel;
  return kBrainLabel;
}

TetMesh makeBrainPhantom(int targetTets, const BrainPhantomRegions& regions) {
  ImplicitSolid solid{brainPhantomDistance, Vec3::Zero(), kBoundingRadius, kVolumeTerm, kSurfaceTerm,
                      kLeastFacetDistance, {}, {}};
  if (regions.any()) {
    solid.region = [regions](const Vec3& p) { return brainPhantomRegion(p, regions); };
    // The regions, small beside the brain, resolved at a third of its size
    // by default (and 5 mm around them): a tumour of 10 mm is then some 20
    // cells across at 22,000 tetrahedra, not 3. Their elements' critical time
    // step is as much smaller (the FEM's mass scaling makes up for it).
    solid.sizeFactor = [regions](const Vec3& p) {
      const double kFiner = 1.0 / regions.detail;
      constexpr double kBand = 5.0;  // mm
      if (regions.tumourRadius > 0 && (p - regions.tumourCentre).norm() < regions.tumourRadius + kBand) return kFiner;
      if (regions.vesselRadius > 0 &&
          std::hypot(p.x() - regions.vesselAxisX(), p.z() - regions.vesselZ) < regions.vesselRadius + kBand)
        return kFiner;
      return 1.0;
    };
  }
  return meshImplicitSolid(solid, targetTets);
}

}  // namespace trephine::tetra
