#include "plugins/tetra_brain/ImplicitMesher.h"

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
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

namespace trephine::tetra {

namespace {

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

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Domain = CGAL::Labeled_mesh_domain_3<Kernel>;
using Triangulation = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using Complex = CGAL::Mesh_complex_3_in_triangulation_3<Triangulation>;
using Criteria = CGAL::Mesh_criteria_3<Triangulation>;

// The domain owns its random generator (initial surface points), so every run
// starts from the same seed whatever ran before.
struct SeededDomain {
  CGAL::Random random{kSeed};
  Domain domain;
  explicit SeededDomain(const ImplicitSolid& solid)
      : domain(Domain::create_implicit_mesh_domain(
            [&solid](const Point& p) { return solid.distance(Vec3(p.x(), p.y(), p.z())); },
            Kernel::Sphere_3(Point(solid.centre.x(), solid.centre.y(), solid.centre.z()),
                             solid.boundingRadius * solid.boundingRadius),
            CGAL::parameters::relative_error_bound = kRelativeErrorBound, CGAL::parameters::p_rng = &random)) {}
};

// Delaunay refinement only (no perturbation or exudation), with cells and
// surface facets of circumradius at most `size` (mm).
Complex refine(const ImplicitSolid& solid, double size) {
  namespace params = CGAL::parameters;
  const SeededDomain seeded(solid);
  // Facet distance follows the size so that the tet count keeps scaling as
  // size^-3 (a fixed one would set a floor of surface tets); a tenth of the
  // size keeps the brain phantom's fissure open down to 3500 tets.
  const double facetDistance = std::max(solid.leastFacetDistance, 0.1 * size);
  const Criteria criteria(params::facet_angle = 25.0, params::facet_size = size, params::facet_distance = facetDistance,
                          params::cell_radius_edge_ratio = 3.0, params::cell_size = size);
  return CGAL::make_mesh_3<Complex>(seeded.domain, criteria, params::no_perturb(), params::no_exude());
}

// Sliver removal: raises the smallest dihedral angle from under 1 deg to 10 deg.
// Time limit 0 is none: the default (the refinement's duration) would make the
// result depend on the machine's speed. Perturbation stops at kPerturbBound
// (without a bound it takes up to 5 s to gain 2 deg more); exudation then runs
// to the end (bound 0), flipping about 4% of the tets away.
void removeSlivers(const ImplicitSolid& solid, Complex& complex) {
  namespace params = CGAL::parameters;
  const SeededDomain seeded(solid);
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

TetMesh meshImplicitSolid(const ImplicitSolid& solid, int targetTets) {
  if (targetTets < kMinTargetTets || targetTets > kMaxTargetTets)
    throw std::invalid_argument("target tetrahedron count " + std::to_string(targetTets) +
                                " is outside [" + std::to_string(kMinTargetTets) + ", " +
                                std::to_string(kMaxTargetTets) + "]");
  // Exudation removes about 4% of the refined mesh's tets (slivers flipped
  // away), whatever the size: refinement aims at the count before it.
  const double refinedTarget = targetTets / kSliverRemovalRetention;
  // First guess of the cell size s (mm) from the solid's estimate of the
  // refined count, solved for s by fixed-point iteration.
  double size = std::cbrt(solid.volumeTerm / refinedTarget);
  for (int i = 0; i < 20; ++i)
    size = std::cbrt(solid.volumeTerm /
                     std::max(refinedTarget - solid.surfaceTerm / (size * size), 0.1 * refinedTarget));
  double exponent = -3.0;  // d log(count) / d log(size), refined from the runs
  Complex best;
  double bestError = std::numeric_limits<double>::infinity(), lastSize = 0.0, lastCount = 0.0;
  for (int run = 0; run < kMaxRuns && bestError > kAim; ++run) {
    Complex complex = refine(solid, size);
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
  removeSlivers(solid, best);
  return toTetMesh(best);
}

TetMesh meshImplicitSolidAtSize(const ImplicitSolid& solid, double size) {
  if (!(size > 0) || !std::isfinite(size)) throw std::invalid_argument("the cell size must be a positive number of mm");
  Complex complex = refine(solid, size);
  removeSlivers(solid, complex);
  return toTetMesh(complex);
}

}  // namespace trephine::tetra
