// All CGAL code of the project lives in this one file: each translation unit
// that includes Mesh_3 takes about half a minute to compile.
#include "plugins/tetra_brain/BrainPhantom.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Random.h>
#include <CGAL/exude_mesh_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/perturb_mesh_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

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

// Squared radius of the bounding sphere of the domain for Mesh_3 (mm^2): 110 mm
// contains the body (farthest point about 88 mm from the origin) with margin.
constexpr double kBoundingSquaredRadius = 110.0 * 110.0;
// Bisection tolerance of surface points, relative to the bounding sphere.
constexpr double kRelativeErrorBound = 1e-6;
// Fixed seed of the initial surface points: the mesh depends only on the target.
constexpr unsigned int kSeed = 20240601;

constexpr int kMinTargetTets = 100;
constexpr int kMaxTargetTets = 2000000;
// Refinement runs at most, and the relative deviation of the refined count
// from its target that ends them early.
constexpr int kMaxRuns = 4;
constexpr double kAim = 0.025;
// Smallest dihedral angle that sliver perturbation aims at (deg).
constexpr double kPerturbBound = 10.0;
// Fraction of the refined mesh's tets left after sliver removal (measured over
// 1.5k to 50k tets: 0.952 to 0.960).
constexpr double kSliverRemovalRetention = 0.957;

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

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Domain = CGAL::Labeled_mesh_domain_3<Kernel>;
using Triangulation = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using Complex = CGAL::Mesh_complex_3_in_triangulation_3<Triangulation>;
using Criteria = CGAL::Mesh_criteria_3<Triangulation>;

double implicitFunction(const Point& p) { return brainPhantomDistance(Vec3(p.x(), p.y(), p.z())); }

// The domain owns its random generator (initial surface points), so every run
// starts from the same seed whatever ran before.
struct SeededDomain {
  CGAL::Random random{kSeed};
  Domain domain = Domain::create_implicit_mesh_domain(
      implicitFunction, Kernel::Sphere_3(CGAL::ORIGIN, kBoundingSquaredRadius),
      CGAL::parameters::relative_error_bound = kRelativeErrorBound, CGAL::parameters::p_rng = &random);
};

// Delaunay refinement only (no perturbation or exudation), with cells and
// surface facets of circumradius at most `size` (mm).
Complex refine(double size) {
  namespace params = CGAL::parameters;
  const SeededDomain seeded;
  // Facet distance follows the size so that the tet count keeps scaling as
  // size^-3 (a fixed one would set a floor of surface tets); a tenth of the size
  // keeps the fissure open down to 3500 tets, and 0.5 mm resolves the gyri.
  const double facetDistance = std::max(0.5, 0.1 * size);
  const Criteria criteria(params::facet_angle = 25.0, params::facet_size = size, params::facet_distance = facetDistance,
                          params::cell_radius_edge_ratio = 3.0, params::cell_size = size);
  return CGAL::make_mesh_3<Complex>(seeded.domain, criteria, params::no_perturb(), params::no_exude());
}

// Sliver removal: raises the smallest dihedral angle from under 1 deg to 10 deg.
// Time limit 0 is none: the default (the refinement's duration) would make the
// result depend on the machine's speed. Perturbation stops at kPerturbBound
// (without a bound it takes up to 5 s to gain 2 deg more); exudation then runs
// to the end (bound 0), flipping about 4% of the tets away.
void removeSlivers(Complex& complex) {
  namespace params = CGAL::parameters;
  const SeededDomain seeded;
  CGAL::perturb_mesh_3(complex, seeded.domain, params::time_limit = 0, params::sliver_bound = kPerturbBound);
  CGAL::exude_mesh_3(complex, params::time_limit = 0, params::sliver_bound = 0.0);
}

TetMesh toTetMesh(const Complex& complex) {
  TetMesh mesh;
  // Nodes are numbered in the order the cells meet them, so the hash only has
  // to be consistent within the call.
  const auto hash = [](Triangulation::Vertex_handle v) { return std::hash<const void*>()(&*v); };
  std::unordered_map<Triangulation::Vertex_handle, int32_t, decltype(hash)> index(0, hash);
  const auto nodeOf = [&](Triangulation::Vertex_handle v) {
    const auto [it, inserted] = index.try_emplace(v, static_cast<int32_t>(mesh.nodes.size()));
    if (inserted) {
      const auto& p = v->point().point();
      mesh.nodes.emplace_back(p.x(), p.y(), p.z());
    }
    return it->second;
  };
  mesh.tets.reserve(complex.number_of_cells_in_complex());
  for (auto cell = complex.cells_in_complex_begin(); cell != complex.cells_in_complex_end(); ++cell) {
    TetIndices tet;
    for (int i = 0; i < 4; ++i) tet[i] = nodeOf(cell->vertex(i));
    const auto& n = mesh.nodes;
    if (signedVolume(n[tet[0]], n[tet[1]], n[tet[2]], n[tet[3]]) < 0) std::swap(tet[2], tet[3]);
    mesh.tets.push_back(tet);
  }
  mesh.labels.assign(mesh.tets.size(), 1);
  return mesh;
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

TetMesh makeBrainPhantom(int targetTets) {
  if (targetTets < kMinTargetTets || targetTets > kMaxTargetTets)
    throw std::invalid_argument("brain phantom: target tetrahedron count " + std::to_string(targetTets) +
                                " is outside [" + std::to_string(kMinTargetTets) + ", " +
                                std::to_string(kMaxTargetTets) + "]");
  // Exudation removes about 4% of the refined mesh's tets (slivers flipped
  // away), whatever the size: refinement aims at the count before it.
  const double refinedTarget = targetTets / kSliverRemovalRetention;
  // First guess of the cell size s (mm) from the refined count of Mesh_3 with
  // these criteria, about 6.0e6 / s^3 (volume) + 2.8e5 / s^2 (surface) for s
  // from 5 to 14 mm, solved for s by fixed-point iteration.
  double size = 5.0;
  for (int i = 0; i < 20; ++i)
    size = std::cbrt(6.0e6 / std::max(refinedTarget - 2.8e5 / (size * size), 0.1 * refinedTarget));
  double exponent = -3.0;  // d log(count) / d log(size), refined from the runs
  Complex best;
  double bestError = std::numeric_limits<double>::infinity(), lastSize = 0.0, lastCount = 0.0;
  for (int run = 0; run < kMaxRuns && bestError > kAim; ++run) {
    Complex complex = refine(size);
    const double count = static_cast<double>(complex.number_of_cells_in_complex());
    const double error = std::abs(count / refinedTarget - 1.0);
    if (error < bestError) {
      bestError = error;
      best.swap(complex);
    }
    if (lastCount > 0 && std::abs(std::log(size / lastSize)) > 1e-3) {
      const double slope = std::log(count / lastCount) / std::log(size / lastSize);
      if (std::isfinite(slope)) exponent = std::clamp(slope, -4.0, -1.5);
    }
    lastSize = size;
    lastCount = count;
    size *= std::pow(refinedTarget / std::max(count, 1.0), 1.0 / exponent);
  }
  removeSlivers(best);
  return toTetMesh(best);
}

}  // namespace trephine::tetra
