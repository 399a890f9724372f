#include "plugins/voxel_skull/Phantoms.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "framework/core/MadeOnce.h"
#include "framework/core/SourceSpec.h"

namespace trephine::voxel {

namespace {

// Fraction of a voxel of side h inside a region whose signed distance at the
// voxel centre is `distance` (negative inside): a linear ramp over one voxel,
// the partial-volume value of a flat boundary crossing the voxel.
double insideFraction(double distance, double h) { return std::clamp(0.5 - distance / h, 0.0, 1.0); }

std::array<int32_t, 3> dimsFor(const Vec3& extent, double voxel) {
  std::array<int32_t, 3> dims;
  for (int a = 0; a < 3; ++a) dims[a] = std::max(1, static_cast<int32_t>(std::ceil(extent[a] / voxel - 1e-9)));
  return dims;
}

void checkVoxel(double voxel, const Vec3& extent) {
  if (!(voxel > 0) || !std::isfinite(voxel)) throw std::invalid_argument("voxel size must be > 0 mm");
  const double count = std::ceil(extent.x() / voxel) * std::ceil(extent.y() / voxel) * std::ceil(extent.z() / voxel);
  if (count > 1.5e9) throw std::invalid_argument("voxel size too small: more than 1.5e9 voxels");
}

// Fills every voxel from density(centre) with the grid centred on the origin,
// then moved by `shift` (mm) along each axis against the shape: where the
// voxel centres fall on a surface (the scan's phase) sets how far the
// interpolated isosurface is from it, so a study of the voxel size averages
// over shifts.
DensityVolume fill(const Vec3& extent, double voxel, const std::function<double(const Vec3&)>& density,
                   double shift = 0.0) {
  checkVoxel(voxel, extent);
  const auto dims = dimsFor(extent, voxel);
  const Vec3 size(dims[0] * voxel, dims[1] * voxel, dims[2] * voxel);
  const Vec3 origin = -0.5 * size + Vec3::Constant(0.5 * voxel + shift);
  DensityVolume volume(dims, Vec3::Constant(voxel), origin);
  for (int32_t k = 0; k < dims[2]; ++k)
    for (int32_t j = 0; j < dims[1]; ++j)
      for (int32_t i = 0; i < dims[0]; ++i) volume.setDensity(i, j, k, density(volume.voxelCenter(i, j, k)));
  return volume;
}

}  // namespace

namespace {

// The phantoms' solids as level sets (mm, negative inside): the density of
// each phantom is built from them, and they are its exact shape.

double cubeLevel(const Vec3& p) { return (p.cwiseAbs() - Vec3::Constant(80.0)).maxCoeff(); }  // distance on the faces

const Vec3 kSkullExtent(212.5, 201.5, 141.5);                           // mm
const Vec3 kSkullOuterAxes = 0.5 * kSkullExtent - Vec3::Constant(1.5);  // mm, semi-axes of the outer surface
constexpr double kSkullOpeningRadius = 16.0;                            // mm, around the -z axis
constexpr double kAirHounsfield = -1000.0;
// The head's segmentation: the brain fills the skull's cavity but for a
// layer of cerebrospinal fluid, above a flat base, with white matter (label
// 2) inside grey matter (label 1) within this fraction of the skull's axes.
constexpr double kHeadCsfGap = 2.0;              // mm
constexpr double kHeadBrainBaseZ = -40.0;        // mm
constexpr double kHeadWhiteMatterRadius = 0.55;  // of the outer surface's semi-axes

// Where a point sits in the skull's shell, along the ray from the centre.
struct SkullDepth {
  double depth = 0;      // mm below the outer surface (negative outside)
  double thickness = 0;  // mm, of the shell in this direction (4.5 to 8.5)
  bool atCentre = false;
};

SkullDepth skullDepth(const Vec3& p) {
  const Vec3 e = p.cwiseQuotient(kSkullOuterAxes);
  const double rho = e.norm();  // 1 on the outer surface
  if (rho < 1e-9) return {.atCentre = true};
  const Vec3 dir = e / rho;
  const double theta = std::acos(std::clamp(dir.z(), -1.0, 1.0)), phi = std::atan2(dir.y(), dir.x());
  return {.depth = p.norm() * (1.0 / rho - 1.0), .thickness = 6.5 + 2.0 * std::sin(3 * theta) * std::cos(2 * phi)};
}

// > 0 where the opening at the base removes bone.
double skullOpening(const Vec3& p) { return p.z() < 0 ? kSkullOpeningRadius - std::hypot(p.x(), p.y()) : -1e9; }

double skullLevel(const Vec3& p) {
  const SkullDepth s = skullDepth(p);
  if (s.atCentre) return 1.0;
  return std::max(std::max(-s.depth, s.depth - s.thickness), skullOpening(p));
}

double halfSpaceLevel(const Vec3& p, const Vec3& unitNormal) { return p.dot(unitNormal); }
double wallLevel(const Vec3& p, double thickness) { return std::abs(p.z()) - 0.5 * thickness; }
struct ChannelParts {
  double fromChannel;  // mm, > 0 in the block around the channel
  double block;        // mm, < 0 inside the block
};
ChannelParts channelParts(const Vec3& p, double width, double size, double voxel) {
  return {std::max(std::abs(p.x()), std::abs(p.y())) - 0.5 * width,
          (p.cwiseAbs() - Vec3::Constant(0.5 * size - 2.0 * voxel)).maxCoeff()};
}
double channelLevel(const Vec3& p, double width, double size, double voxel) {
  const ChannelParts c = channelParts(p, width, size, voxel);
  return std::max(-c.fromChannel, c.block);
}

Vec3 unitNormal(const Vec3& normal) {
  if (!(normal.norm() > 1e-9) || !normal.allFinite()) throw std::invalid_argument("normal must not be zero");
  return normal.normalized();
}

}  // namespace

DensityVolume makeCubePhantom(int voxelsPerAxis, double density) {
  if (voxelsPerAxis < 2 || voxelsPerAxis > 2000) throw std::invalid_argument("voxels must be in [2, 2000]");
  const double voxel = 200.0 / voxelsPerAxis;
  return fill(Vec3::Constant(200.0), voxel,
              [&](const Vec3& p) { return density * insideFraction(cubeLevel(p), voxel); });
}

std::array<int32_t, 3> skullPhantomDims(double voxel) { return dimsFor(kSkullExtent, voxel); }

DensityVolume makeSkullPhantom(double voxel, double shift) {
  return fill(kSkullExtent, voxel, [&](const Vec3& p) {
    const auto [depth, thickness, atCentre] = skullDepth(p);
    if (atCentre) return 40.0;
    const double table = 0.25 * thickness;  // each cortical table (mm)
    const double inBone = insideFraction(std::max(-depth, depth - thickness), voxel);
    const double inOuterTable = insideFraction(depth - table, voxel);
    const double inInnerTable = insideFraction(thickness - table - depth, voxel);
    const double boneDensity = 700.0 + 800.0 * inOuterTable + 600.0 * inInnerTable;
    // Opening at the base: no bone within 16 mm of the -z axis.
    const double opening = p.z() < 0 ? insideFraction(-skullOpening(p), voxel) : 0.0;
    const double inCavity = insideFraction(thickness - depth, voxel);
    return inBone * (1.0 - opening) * boneDensity + inCavity * 40.0;
  }, shift);
}

DensityVolume makeHeadPhantom(double voxel) {
  const DensityVolume skull = makeSkullPhantom(voxel);
  return fill(kSkullExtent, voxel, [&](const Vec3& p) {
    // The skull phantom's densities are CT numbers with air at 0; a CT in
    // Hounsfield units has air at -1000.
    const SkullDepth s = skullDepth(p);
    const double outside = s.atCentre ? 0.0 : 1.0 - insideFraction(-s.depth, voxel);
    const Eigen::Vector3i index = ((p - skull.origin()).cwiseQuotient(skull.spacing())).array().round().cast<int>();
    return skull.density(index.x(), index.y(), index.z()) + kAirHounsfield * outside;
  });
}

DensityVolume makeHeadLabelsPhantom(double voxel) {
  return fill(kSkullExtent, voxel, [&](const Vec3& p) {
    const SkullDepth s = skullDepth(p);
    if (!s.atCentre && s.depth < s.thickness + kHeadCsfGap) return 0.0;  // bone, CSF and outside
    if (p.z() < kHeadBrainBaseZ) return 0.0;
    const double rho = p.cwiseQuotient(kSkullOuterAxes).norm();
    return rho < kHeadWhiteMatterRadius ? 2.0 : 1.0;
  });
}

DensityVolume makeHalfSpacePhantom(double voxel, const Vec3& normal, double size, double density) {
  const Vec3 n = unitNormal(normal);
  return fill(Vec3::Constant(size), voxel, [&](const Vec3& p) {
    // Partial volume of a tilted plane: the ramp width is the voxel's extent along n.
    const double width = voxel * n.cwiseAbs().sum();
    return density * std::clamp(0.5 - halfSpaceLevel(p, n) / width, 0.0, 1.0);
  });
}

DensityVolume makeWallPhantom(double voxel, double thickness, double size, double density) {
  return fill(Vec3::Constant(size), voxel,
              [&](const Vec3& p) { return density * insideFraction(wallLevel(p, thickness), voxel); });
}

DensityVolume makeChannelPhantom(double voxel, double width, double size, double density) {
  return fill(Vec3::Constant(size), voxel, [&](const Vec3& p) {
    const ChannelParts c = channelParts(p, width, size, voxel);
    return density * insideFraction(-c.fromChannel, voxel) * insideFraction(c.block, voxel);
  });
}

namespace {

// A phantom named by its specification: how to build its volume, and its exact shape.
struct PhantomDefinition {
  std::function<DensityVolume()> volume;
  LevelSet shape;
};

PhantomDefinition definePhantom(const std::string& specification) {
  const auto [name, query] = SourceSpec::split(specification);
  if (name == "cube") {
    const SourceSpec k(name, query, {{"voxels", 200}, {"density", 1200}});
    const int voxels = k.wholeNumber("voxels", 2, 2000);
    const double density = k.number("density");
    return {[=] { return makeCubePhantom(voxels, density); }, cubeLevel};
  }
  if (name == "skull") {
    const SourceSpec k(name, query, {{"voxel", 1.0}, {"shift", 0.0}});
    const double voxel = k.positive("voxel"), shift = k.number("shift");
    if (!(std::abs(shift) < voxel))
      throw std::invalid_argument("phantom key 'shift' must be less than a voxel (" + std::to_string(voxel) +
                                  " mm) either way, not " + std::to_string(shift));
    return {[=] { return makeSkullPhantom(voxel, shift); }, skullLevel};
  }
  if (name == "halfspace") {
    const SourceSpec k(name, query, {{"voxel", 0.5}, {"nx", 0}, {"ny", 0}, {"nz", 1}, {"size", 40}, {"density", 1000}});
    const double voxel = k.positive("voxel"), size = k.positive("size"), density = k.number("density");
    const Vec3 normal(k.number("nx"), k.number("ny"), k.number("nz"));
    return {[=] { return makeHalfSpacePhantom(voxel, normal, size, density); },
            [n = unitNormal(normal)](const Vec3& p) { return halfSpaceLevel(p, n); }};
  }
  if (name == "wall") {
    const SourceSpec k(name, query, {{"voxel", 0.5}, {"thickness", 0.5}, {"size", 40}, {"density", 1000}});
    const double voxel = k.positive("voxel"), thickness = k.number("thickness"), size = k.positive("size"),
                 density = k.number("density");
    return {[=] { return makeWallPhantom(voxel, thickness, size, density); },
            [=](const Vec3& p) { return wallLevel(p, thickness); }};
  }
  if (name == "channel") {
    const SourceSpec k(name, query, {{"voxel", 0.5}, {"width", 3}, {"size", 40}, {"density", 1000}});
    const double voxel = k.positive("voxel"), width = k.number("width"), size = k.positive("size"),
                 density = k.number("density");
    return {[=] { return makeChannelPhantom(voxel, width, size, density); },
            [=](const Vec3& p) { return channelLevel(p, width, size, voxel); }};
  }
  if (name == "head" || name == "head-labels") {
    const SourceSpec k(name, query, {{"voxel", 1.0}});
    const double voxel = k.positive("voxel");
    if (name == "head") return {[=] { return makeHeadPhantom(voxel); }, skullLevel};
    return {[=] { return makeHeadLabelsPhantom(voxel); }, skullLevel};
  }
  throw std::invalid_argument("unknown phantom '" + name + "' (cube, skull, head, head-labels, halfspace, wall, channel)");
}

}  // namespace

DensityVolume makePhantom(const std::string& specification) {
  // Filling the skull takes about 0.3 s at 1 mm (seconds under a sanitizer):
  // kept for the process's next load of the same phantom (the last four, each
  // up to 64 MB: the skull at 1 mm is 17 MB, at 0.5 mm 97 MB).
  static MadeOnce<DensityVolume> made(4, size_t(64) << 20, [](const DensityVolume& volume) {
    return volume.voxelCount() * sizeof(VoxelCode);
  });
  const auto definition = definePhantom(specification);  // refuses a bad one every time
  return made.get(specification, definition.volume);
}

LevelSet phantomShape(const std::string& specification) { return definePhantom(specification).shape; }

std::string phantomHelp() {
  return "  cube?voxels=200&density=1200          160 mm solid cube in a 200 mm grid of voxels^3 (Table 3.1)\n"
         "  skull?voxel=1.0&shift=0               skull shell, 212.5 x 201.5 x 141.5 mm (Table 3.2: 1.5 .. 0.5);\n"
         "                                        shift (mm, under a voxel) moves the voxels against the shape\n"
         "  head?voxel=1.0                        the skull as a CT in Hounsfield units (air -1000, brain 40,\n"
         "                                        bone 700 to 1500); with --out DIR/ a DICOM series\n"
         "  head-labels?voxel=1.0                 its brain's segmentation: grey matter 1, white matter 2, 0 else\n"
         "  halfspace?voxel=0.5&nx=0&ny=0&nz=1&size=40&density=1000   solid below a plane through the centre\n"
         "  wall?voxel=0.5&thickness=0.5&size=40&density=1000        wall across z = 0\n"
         "  channel?voxel=0.5&width=3&size=40&density=1000           block with a square channel along z\n";
}

}  // namespace trephine::voxel
